"""epuck layer of epuck_vrep_compat: the e-puck robot family, beside the cell: the swarm as an
extension of the simulation (:mod:`.swarm`: robots, commands and watchdog, LEDs, noise), its
components (wheel joints, IR cones: :mod:`.components`), LEDs, cameras rendered together, noise
settings, presets and the paper's numbers, and the e-puck2's extra sensors (an extension,
:mod:`.epuck2_sensors`)."""
