"""The fixed frames of the simulator's TF tree (REP 105), defined once; the e-pucks' own frames
under their ``base_link`` are in :mod:`.epuck_names`."""
WORLD_FRAME = "world"       # V-REP's absolute frame: tf parents, absolute poses
ODOM_FRAME = "odom"         # the fixed frame of the e-pucks (and the cell's odom)
