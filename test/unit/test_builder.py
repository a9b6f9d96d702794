"""The one builder (builder/build.py) and the random streams it derives by name
(builder/streams.py)."""
import hashlib
import os

import pytest

from epuck_vrep_compat.builder.build import SimulationConfig, build_simulation
from epuck_vrep_compat.builder.streams import (
    CELL_KINECT, CELL_LASER, EPUCK2_MAGNETOMETER, EPUCK2_TOF, stream_seed)
from epuck_vrep_compat.epuck.epuck2_sensors import Epuck2Settings
from epuck_vrep_compat.scene.scene_file import SceneError, load_scene, parse_scene
from epuck_vrep_compat.sim.simulation import Simulation
from repo import REPO


def test_a_stream_seed_is_sha256_of_the_seed_and_the_name():
    digest = hashlib.sha256((7).to_bytes(8, "little") + b"cell/laser").digest()
    assert stream_seed(7, CELL_LASER) == int.from_bytes(digest[:8], "little")
    assert 0 <= stream_seed(2 ** 63 - 1, CELL_LASER) < 2 ** 64


def test_every_stream_has_its_own_seed_for_every_seed():
    names = (CELL_LASER, CELL_KINECT, EPUCK2_TOF, EPUCK2_MAGNETOMETER)
    seeds = {stream_seed(seed, name) for seed in range(20) for name in names}
    assert len(seeds) == 20 * len(names)
    assert stream_seed(3, EPUCK2_TOF) == stream_seed(3, EPUCK2_TOF)


def test_the_builder_adds_the_extensions_the_scene_and_the_config_ask_for():
    arena = load_scene(os.path.join(REPO, "worlds", "arena.yaml"))
    plain = build_simulation(arena, SimulationConfig(["ePuck0"]))
    assert plain.cell is None and plain.epuck2 is None and plain.extensions == [plain.epucks]
    assert plain.epucks.robot_names == ["ePuck0"]
    sim = build_simulation(arena, SimulationConfig(["ePuck0"], seed=5, epuck2=Epuck2Settings()))
    assert sim.extensions == [sim.epucks, sim.epuck2]
    cell = build_simulation(load_scene(os.path.join(REPO, "worlds", "merlin_cell.yaml")),
                            SimulationConfig(epuck2=Epuck2Settings()))
    assert cell.extensions == [cell.epucks, cell.cell, cell.epuck2]     # the order they step
    cell.cell.close()
    assert (sim.epuck2.tof_seed, sim.epuck2.mag_seed) == (
        stream_seed(5, EPUCK2_TOF), stream_seed(5, EPUCK2_MAGNETOMETER))


def test_the_simulation_alone_refuses_a_scene_with_a_cell_or_robots():
    scene = load_scene(os.path.join(REPO, "worlds", "merlin_cell.yaml"))
    with pytest.raises(SceneError, match="'cell' section.*build_simulation"):
        Simulation(scene)
    robots = parse_scene({"robots": [{"position_m": [0.0, 0.0]}]})
    with pytest.raises(SceneError, match="'robots' section.*e-pucks'.*build_simulation"):
        Simulation(robots)
    assert Simulation(parse_scene({})).extensions == []          # the world alone: no robots
