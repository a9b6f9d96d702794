"""The one builder: a :class:`Simulation` from a scene and a config, with every extension the
scene and the config ask for, each seeded from the one seed by name (:mod:`.streams`).

The simulator node, the tests and the benchmarks build every simulation here. In the order
they step: the e-pucks (always; none when the config names no robot), the scene's industrial
cell (when it has a ``cell:`` section; pybullet is loaded only then), then the e-puck2's extra
sensors (when the config has their settings: a profile with extra topics), which thus see the
e-pucks and the cell's links where they are; last, only when the config asks (tests), the fault
hook (:mod:`epuck_vrep_compat.sim.fault_hook`).
"""
from dataclasses import dataclass
from typing import Callable, FrozenSet, Optional, Sequence

from epuck_vrep_compat.builder.streams import (
    CELL_KINECT, CELL_LASER, EPUCK2_MAGNETOMETER, EPUCK2_TOF, stream_seed)
from epuck_vrep_compat.devices.components import CameraSpec
from epuck_vrep_compat.epuck.epuck2_sensors import READINGS, Epuck2Sensors, Epuck2Settings
from epuck_vrep_compat.epuck.noise import NoiseSettings
from epuck_vrep_compat.epuck.swarm import CMD_TIMEOUT_S, EpuckRobots
from epuck_vrep_compat.scene.scene_file import Scene
from epuck_vrep_compat.sim.simulation import SEED, STEP_S, Simulation


@dataclass
class SimulationConfig:
    """Everything a simulation is built with besides its scene (the node's parameters): the
    first seven are the arguments of :class:`Simulation` (``step_s``, ``seed``) and of
    :class:`EpuckRobots` (the others), under the same names and with their defaults."""

    robot_names: Sequence[str] = ()
    step_s: float = STEP_S
    seed: int = SEED
    noise: Optional[NoiseSettings] = None           # None: the paper's real robot
    cmd_timeout_s: float = CMD_TIMEOUT_S
    camera: Optional[CameraSpec] = None             # None: the e-puck's camera
    robot_namer: Optional[Callable[[int], str]] = None   # None: V-REP's ePuck<k>
    epuck2: Optional[Epuck2Settings] = None         # the e-puck2's extra sensors; None: none
    epuck2_readings: FrozenSet[str] = READINGS      # which of them (a profile's extras)
    fault_hook: bool = False                        # tests only: faults on command


def build_simulation(scene: Scene, config: SimulationConfig = None) -> Simulation:
    """The simulation of ``scene``. Its ``epucks`` attribute is the
    :class:`~epuck_vrep_compat.epuck.swarm.EpuckRobots`, its ``cell`` attribute the scene's
    :class:`~epuck_vrep_compat.cell.cell.Cell` (or None), its ``epuck2`` attribute the
    :class:`~epuck_vrep_compat.epuck.epuck2_sensors.Epuck2Sensors` (or None), its ``fault_hook``
    attribute the :class:`~epuck_vrep_compat.sim.fault_hook.FaultHook` (or None), each added to
    the simulation's extensions. SceneError when the scene's robots find no place."""
    c = config if config is not None else SimulationConfig()
    sim = Simulation(scene, c.step_s, c.seed, extended_sections=("robots", "cell"))
    sim.epucks = EpuckRobots(sim, c.seed, c.robot_names, c.noise, c.cmd_timeout_s, c.camera,
                             c.robot_namer)
    sim.add_extension(sim.epucks)
    sim.cell = None
    if scene.cell is not None:
        from epuck_vrep_compat.cell.cell import Cell     # pybullet only when a cell is used
        sim.cell = Cell(sim, scene.cell, stream_seed(c.seed, CELL_LASER),
                        stream_seed(c.seed, CELL_KINECT))
        sim.add_extension(sim.cell)
    sim.epuck2 = None
    if c.epuck2 is not None:
        sim.epuck2 = Epuck2Sensors(sim.epucks, c.epuck2, stream_seed(c.seed, EPUCK2_TOF),
                                   stream_seed(c.seed, EPUCK2_MAGNETOMETER), scene.floor_regions,
                                   scene.arena.floor_color, readings=c.epuck2_readings)
        sim.add_extension(sim.epuck2)
    sim.fault_hook = None
    if c.fault_hook:
        from epuck_vrep_compat.sim.fault_hook import FaultHook
        sim.fault_hook = FaultHook()
        sim.add_extension(sim.fault_hook)
    return sim


def rewind_simulation(sim: Simulation, seed: int, walk_seed: int = None):
    """``sim`` back to time 0 as :func:`build_simulation` made it, but seeded ``seed`` (its
    noise streams derived by name as at build) and, with ``walk_seed``, the cell's operator
    walking the walk of that seed (``~operator_walk_seed``'s). ValueError, changing nothing,
    for a walk seed without a cell operator, or a new seed with the e-puck2's sensors (their
    streams are not reseeded)."""
    if walk_seed is not None and (sim.cell is None or sim.cell.operator is None):
        raise ValueError("operator_walk_seed: the scene has no cell operator")
    if sim.epuck2 is not None and seed != sim.seed:
        raise ValueError("a new seed with the e-puck2's sensors (their streams are not "
                         "reseeded)")
    sim.seed = sim.epucks.seed = int(seed)
    if sim.cell is not None:
        sim.cell.laser_seed = stream_seed(seed, CELL_LASER)
        sim.cell.kinect_seed = stream_seed(seed, CELL_KINECT)
        if walk_seed is not None:
            sim.cell.operator.rewalk(walk_seed)
    sim.rewind()
