"""The unit tier's shared set-up (no master): a running ``/vrep`` backend on a shipped world.

Other shared pieces of the tier: ``fake_ros`` (stand-ins for rospy's parts a client node
touches) and ``fixtures/`` (the experiment specs' files); ``repo.REPO`` is the checkout.
"""
import os

import pytest

from epuck_vrep_compat.builder.build import SimulationConfig, build_simulation
from epuck_vrep_compat.scene.model_files import ModelLibrary
from epuck_vrep_compat.scene.scene_file import load_scene
from epuck_vrep_compat.sim.control import RUNNING, SimulationControl
from epuck_vrep_compat.vrep.backend import VrepBackend
from repo import REPO


@pytest.fixture
def backend_of():
    """A factory: ``backend_of(world, robots=())`` is the ``/vrep`` backend of a running,
    real-time simulation of ``worlds/<world>`` with e-pucks of those names and the shipped
    models; each cell it built is closed after the test."""
    made = []

    def factory(world, robots=()):
        sim = build_simulation(load_scene(os.path.join(REPO, "worlds", world)),
                               SimulationConfig(list(robots)))
        made.append(sim)
        return VrepBackend(sim, SimulationControl(sim, RUNNING), real_time=True,
                           models=ModelLibrary(os.path.join(REPO, "models")))

    yield factory
    for sim in made:
        if sim.cell is not None:
            sim.cell.close()
