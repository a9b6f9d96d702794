"""cell layer of epuck_vrep_compat: the industrial cell's robots (IRB 140, SMART SiX, youBot)."""
