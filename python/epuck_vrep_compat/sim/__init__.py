"""sim layer of epuck_vrep_compat: the simulation, its run control, arena and noise, and the
interface of its extensions (:mod:`.extension`)."""
