"""A refused request changes nothing (no master): poses beyond the world or not finite are
refused before anything is stored, for the cell's robots, its free objects and e-pucks; the
simulation steps, resets and answers group data afterwards; big model files are refused before
they are parsed."""
import os

import numpy as np
import pytest

from epuck_vrep_compat.builder.build import SimulationConfig, build_simulation
from epuck_vrep_compat.compat import vrep_codes as vc
from epuck_vrep_compat.scene.model_files import MAX_MODEL_FILE_BYTES, ModelLibrary
from epuck_vrep_compat.scene.scene_file import load_scene
from epuck_vrep_compat.sim.control import RUNNING, SimulationControl
from epuck_vrep_compat.vrep.backend import VrepBackend, VrepError
from epuck_vrep_compat.vrep.group_data import group_data
from repo import REPO


def make_backend(world, robots, model_dirs=()):
    sim = build_simulation(load_scene(os.path.join(REPO, "worlds", world)),
                           SimulationConfig(robots))
    return VrepBackend(sim, SimulationControl(sim, RUNNING), real_time=True,
                       models=ModelLibrary(os.path.join(REPO, "models"), model_dirs))


@pytest.fixture(scope="module")
def cell():
    backend = make_backend("merlin_cell.yaml", [])
    yield backend
    backend.sim.cell.close()


def snapshot(backend):
    """Every object's world pose and every joint's position."""
    registry = backend.sim.registry
    return {o.handle: np.concatenate(registry.world_pose(o.handle))
            for o in registry.objects()}


BAD_POSITIONS = [(2e6, 0.0, 0.0), (0.0, 0.0, -2e6), (0.0, -1e308, 0.0), (float("nan"), 0, 0),
                 (1e6 + 1.0, 1e6 + 1.0, 0.0)]


@pytest.mark.parametrize("name", ["IRB140", "SIX", "youBot", "probe"])
@pytest.mark.parametrize("position", BAD_POSITIONS)
def test_a_refused_pose_stores_nothing_and_the_cell_steps_on(cell, name, position):
    handle = cell.sim.registry.handle_of(name)
    assert handle >= 0, name
    cell.sim.step()
    before = snapshot(cell)
    with pytest.raises(VrepError):
        cell.set_pose(handle, vc.WORLD, position=position)
    with pytest.raises(VrepError):
        cell.set_pose(handle, vc.WORLD, position=position, quat=(0.0, 0.0, 0.0, 1.0))
    after = snapshot(cell)
    assert after.keys() == before.keys()
    for h in before:
        np.testing.assert_array_equal(after[h], before[h], err_msg=str(h))
    for _ in range(3):
        cell.sim.step()                       # raised ValueError before the fix
    cell.sim.reset()
    _, _, floats, _ = group_data(cell, vc.OBJECT_JOINT, 9)    # absolute poses
    assert floats and np.all(np.isfinite(floats))


def test_a_base_inside_the_world_with_links_beyond_it_is_rolled_back(cell):
    """The base passes the backend's check, its links do not pass the core's: the move is
    undone and refused."""
    six = cell.sim.registry.handle_of("SIX")
    before = snapshot(cell)
    with pytest.raises(VrepError, match="within ±1e6 m"):
        cell.set_pose(six, vc.WORLD, position=(0.0, 0.0, 999999.9))
    assert all(np.array_equal(snapshot(cell)[h], p) for h, p in before.items())
    cell.sim.step()


def test_a_valid_move_still_moves(cell):
    six = cell.sim.registry.handle_of("SIX")
    old, _ = cell.pose(six)
    cell.set_pose(six, vc.WORLD, position=old + (0.5, 0.0, 0.0))
    np.testing.assert_allclose(cell.pose(six)[0], old + (0.5, 0.0, 0.0), atol=1e-9)
    cell.sim.step()
    cell.sim.reset()
    np.testing.assert_allclose(cell.pose(six)[0], old, atol=1e-9)


def test_an_epuck_refuses_a_pose_beyond_the_world():
    backend = make_backend("arena.yaml", ["ePuck0"])
    base = backend.sim.registry.handle_of("ePuck0")
    before = snapshot(backend)
    with pytest.raises(VrepError):
        backend.set_pose(base, vc.WORLD, position=(2e6, 0.0, 0.0))
    assert all(np.array_equal(snapshot(backend)[h], p) for h, p in before.items())
    backend.sim.step()


def test_a_big_model_file_is_refused_before_it_is_parsed(tmp_path):
    path = tmp_path / "big.yaml"
    path.write_text("robot: epuck\nfiller: [" + "1, " * (MAX_MODEL_FILE_BYTES // 3) + "1]\n")
    backend = make_backend("arena.yaml", [], [str(tmp_path)])
    with pytest.raises(VrepError, match="at most"):
        backend.read_model(str(path))
    assert backend.sim.epucks.size == 0
