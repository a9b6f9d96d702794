"""The cell's vision sensors read in parts: the Kinect's depth alone and colour alone are
render()'s images bit for bit and draw the same depth noise, and ``/vrep``'s depth buffer is
V-REP's normalisation of them (no master)."""
import os

import numpy as np
import pytest

from epuck_vrep_compat.builder.build import SimulationConfig, build_simulation
from epuck_vrep_compat.scene.scene_file import load_scene
from epuck_vrep_compat.sim.control import RUNNING, SimulationControl
from epuck_vrep_compat.vrep.backend import VrepBackend
from repo import REPO

WORLD = os.path.join(REPO, "worlds", "merlin_cell.yaml")


@pytest.fixture
def twins():
    """Two cells of the same seed, 40 steps in (the operator in the Kinect's view)."""
    made = [build_simulation(load_scene(WORLD), SimulationConfig([], seed=3)) for _ in range(2)]
    for sim in made:
        for _ in range(40):
            sim.step()
    yield made
    for sim in made:
        sim.cell.close()


def test_depth_alone_and_colour_alone_are_the_whole_rendering(twins):
    whole, parts = (sim.cell for sim in twins)
    for _ in range(2):                     # the second time on the noise stream drawn so far
        rgb, depth = whole.kinect_depth.render()
        assert np.array_equal(parts.kinect_depth.render_depth(), depth)
        assert np.array_equal(parts.kinect_rgb.render_rgb(), whole.kinect_rgb.render()[0])
        # the noisy sensor's colour image draws one image's noise, as a whole rendering does
        assert np.array_equal(parts.kinect_depth.render_rgb(), whole.kinect_depth.render()[0])
    assert len(np.unique(depth)) > 1000    # noise on a scene, not a blank image
    for mine, theirs in zip(whole.cameras, parts.cameras):        # the ceiling cameras
        assert np.array_equal(mine.render_depth(), theirs.render()[1])
        assert np.array_equal(mine.render_rgb(), theirs.render()[0])


def test_the_depth_buffer_is_v_reps_normalisation_of_the_noisy_depth(twins):
    whole, parts = twins
    sensor = whole.cell.kinect_depth
    backend = VrepBackend(parts, SimulationControl(parts, RUNNING), real_time=False)
    resolution, buffer = backend.vision_depth(parts.cell.kinect_depth.handle)
    s = sensor.spec
    expected = np.clip((sensor.render()[1].astype(np.float64) - s.near_m) / (s.far_m - s.near_m),
                       0.0, 1.0)[::-1].astype(np.float32)
    assert resolution == (s.width, s.height)
    assert buffer.dtype == np.float32 and buffer.flags.c_contiguous
    assert np.array_equal(buffer, expected)
    assert len(np.unique(buffer)) > 1000
