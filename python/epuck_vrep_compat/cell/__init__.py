"""cell layer of epuck_vrep_compat: the industrial cell (IRB 140, SMART SiX, youBot, operator,
sensors) as an extension of the simulation (:mod:`.cell`), its devices (:mod:`.devices`), and
:func:`.world.build_simulation`, which builds a scene's simulation with its cell."""
