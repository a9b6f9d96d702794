"""sim layer of epuck_vrep_compat: the world, which knows no robot family: the simulation
(registry, collision world, arena, signals, time, the one lock), the interface of its extensions
(:mod:`.extension`, which every robot family implements), and run control."""
