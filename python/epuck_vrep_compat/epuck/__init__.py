"""epuck layer of epuck_vrep_compat: the e-puck robot family: its components (wheel joints, IR
cones: :mod:`.components`), LEDs, cameras rendered together, noise settings, presets and the
paper's numbers, and the e-puck2's extra sensors (an extension, :mod:`.epuck2_sensors`).

Below ``sim`` while :class:`~epuck_vrep_compat.sim.simulation.Simulation` still holds the
swarm itself (issue 23); once the swarm is an extension, as the cell is, it moves up beside
``cell``."""
