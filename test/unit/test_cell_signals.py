"""The cell's model-side outputs the ROS faces read (no master): the blob float signals the
cell writes after each step (as the thesis's child script), cleared when a camera goes, and
the count of laser scans taken."""
import os

import pytest

from epuck_vrep_compat.scene.model_files import ModelLibrary
from epuck_vrep_compat.scene.scene_file import load_scene
from epuck_vrep_compat.sim.control import RUNNING, SimulationControl
from epuck_vrep_compat.sim.simulation import Simulation
from epuck_vrep_compat.vrep.backend import VrepBackend, VrepError

REPO = os.path.join(os.path.dirname(__file__), "..", "..")


@pytest.fixture
def backend():
    sim = Simulation(load_scene(os.path.join(REPO, "worlds", "merlin_cell.yaml")), [])
    yield VrepBackend(sim, SimulationControl(sim, RUNNING), real_time=True,
                      models=ModelLibrary(os.path.join(REPO, "models")))
    sim.cell.close()


def test_blob_signals_follow_each_step_and_go_with_their_camera(backend):
    sim = backend.sim
    assert sim.signals["float"] == {}              # written by steps only
    for _ in range(3):
        sim.step()
        for camera in sim.cell.camera_specs:
            packet = sim.cell.blobs[camera.name]
            x_topic, y_topic = camera.blob_topics
            if packet[0] >= 1:
                assert backend.signal("float", x_topic) == float(packet[4])
                assert backend.signal("float", y_topic) == float(packet[5])
            else:
                assert x_topic not in sim.signals["float"]
                assert y_topic not in sim.signals["float"]
    assert "Blob_Camera_0_X" in sim.signals["float"]      # camera0 sees the operator at start
    backend.remove_object(sim.registry.handle_of("camera0"))
    with pytest.raises(VrepError):
        backend.signal("float", "Blob_Camera_0_X")


def test_scan_count_counts_the_scans_taken(backend):
    cell = backend.sim.cell
    every = cell._scan_every
    before = cell.scan_count
    for _ in range(4 * every):
        backend.sim.step()
    assert cell.scan_count == before + 4
