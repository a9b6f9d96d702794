"""What a :class:`~epuck_vrep_compat.sim.simulation.Simulation` asks of the things that extend
it (the e-pucks, the industrial cell, the e-puck2's sensors): a narrow interface, so the
simulation never names them. Each robot family's package holds its extensions
(:mod:`epuck_vrep_compat.epuck.swarm`, :mod:`epuck_vrep_compat.cell.cell`); the builder adds
them.

An extension registers its own objects in ``sim.registry`` and ``sim.world`` and gives them
behaviour; the simulation calls these hooks, in the order the extensions were added, whenever
an object may be one of theirs (removal, moves, velocities, a model loaded) and once per step
and reset. The defaults claim nothing and do nothing.
"""


class SimulationExtension:
    """Base class of the simulation's extensions; override the hooks an extension needs."""

    def owns(self, obj) -> bool:
        """Whether the extension moves ``obj`` (a registry object): then :meth:`move_object`
        and :meth:`object_velocity` answer for it."""
        return False

    def claims_removal(self, obj) -> bool:
        """simRemoveObject on ``obj``: True when the extension's object may go (the simulation
        removes it with its descendants, then calls :meth:`forget`), False when ``obj`` is not
        the extension's; ValueError for a part that only goes with its whole."""
        return False

    def forget(self, removed: set) -> None:
        """After the simulation removed these handles from the registry and the world."""

    def move_object(self, obj, position, quat) -> None:
        """Teleport an owned object; ValueError (leaving everything as it was) when refused."""
        raise ValueError(f"'{obj.name}' cannot be placed")

    def object_velocity(self, obj):
        """(linear (3), angular (3)) world velocity of an owned object."""
        raise NotImplementedError

    def step(self, dt: float) -> None:
        """One step of ``dt`` seconds, after the extensions added before stepped (the frame
        counter already advanced: ``sim.time_s`` is the step's end)."""

    def reset(self) -> None:
        """Back to the start (robots at their start poses, noise restarted), after the
        extensions added before."""

    def published_signals(self):
        """(kind, name) of the signals the extension's scripts publish from every start on, as
        V-REP's child scripts enabled a signal's publisher stream in their first pass; ``kind``
        is a key of ``Simulation.signals``. The ``/vrep`` face enables those streams itself."""
        return ()

    def load_model(self, model):
        """simLoadModel of a model file (``scene.model_files.ModelFile``): the new robot (an
        object whose ``root`` is its base object), or None when the model is not this
        extension's; ValueError (nothing changed) when refused. The simulation calls its
        listeners afterwards."""
        return None
