"""compat layer of epuck_vrep_compat: every compatibility name and code, defined once, in plain
Python (no ROS, nothing compiled), so that every layer and every client node may import it.

:mod:`.vrep_codes` V-REP's numeric codes; :mod:`.topics` the simulator node's name and the
topics and services shared with clients; :mod:`.frames` the fixed TF frames;
:mod:`.epuck_names` the e-puck topic profiles' robot, topic and frame names;
:mod:`.cell_names` the cell robots' V-REP names; :mod:`.thesis_names` the thesis's nodes and
topics."""
