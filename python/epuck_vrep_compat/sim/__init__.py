"""sim layer of epuck_vrep_compat: the simulation, its run control and arena (the e-puck
family's parts it holds are in :mod:`epuck_vrep_compat.epuck`; its extensions' interface in
:mod:`epuck_vrep_compat.devices.extension`)."""
