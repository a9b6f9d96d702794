"""cell layer of epuck_vrep_compat: the industrial cell (IRB 140, SMART SiX, youBot, operator,
sensors) as an extension of the simulation (:mod:`.cell`) and its devices (:mod:`.devices`);
:func:`epuck_vrep_compat.builder.build.build_simulation` adds it to a scene's simulation."""
