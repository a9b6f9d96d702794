"""scene layer of epuck_vrep_compat: scene and model files, their checks, the object registry,
transforms, placement, the e-puck model, the cell robots' names and the V-REP codes. Light:
the client nodes import parts of it (:mod:`.vrep_codes`, :mod:`.robots`)."""
