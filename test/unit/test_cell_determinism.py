"""The cell runs the same twice: the same seed and the same commands give bit-identical joint
states, laser scans, Kinect depth and blobs after 200 steps, in two simulations and after
reset-and-rerun; another seed gives other noise; a simulation rewound to another seed and walk
runs as one built with them (no master)."""
import os

import numpy as np
import pytest

from epuck_vrep_compat.builder.build import SimulationConfig, build_simulation, rewind_simulation
from epuck_vrep_compat.scene.operator_file import override_motion
from epuck_vrep_compat.scene.scene_file import load_scene
from repo import REPO

WORLD = os.path.join(REPO, "worlds", "merlin_cell.yaml")
STEPS = 200


def run(sim):
    """200 steps with a client's commands from step 50 on; the state that matters."""
    cell = sim.cell
    irb, youbot = cell.arm_by_name["IRB140"], cell.arm_by_name["youBot"]
    for k in range(STEPS):
        if k == 50:
            irb.joints[0].set_target_position(0.8)
            irb.joints[2].set_target_velocity(-0.3)
            youbot.set_twist(0.1, -0.05, 0.2)
        sim.step()
    depth = cell.kinect_depth.render()[1]
    return (np.concatenate([a.q for a in cell.arms]), np.concatenate([a.qd for a in cell.arms]),
            cell.laser_ranges.copy(), depth, cell.blobs["camera0"].copy(),
            cell.blobs["camera"].copy(), cell.prox_distance.copy())


@pytest.fixture
def sims():
    made = []

    def make(seed, walk_seed=None):
        scene = load_scene(WORLD)
        scene.cell.operator = override_motion(scene.cell.operator, walk_seed)
        sim = build_simulation(scene, SimulationConfig([], seed=seed))
        made.append(sim)
        return sim
    yield make
    for sim in made:
        sim.cell.close()


def assert_identical(a, b):
    for x, y in zip(a, b):
        np.testing.assert_array_equal(x, y)


def test_same_seed_same_commands_same_run_and_after_reset(sims):
    first, second = sims(7), sims(7)
    a = run(first)
    assert_identical(a, run(second))
    first.reset()
    assert_identical(a, run(first))


def test_another_seed_gives_other_noise(sims):
    a, b = run(sims(7)), run(sims(8))
    np.testing.assert_array_equal(a[0], b[0])             # the same motion ...
    assert not np.array_equal(a[2], b[2])                  # ... but other laser noise
    assert not np.array_equal(a[3], b[3])                  # and other depth noise


def test_rewound_to_another_seed_and_walk_it_runs_as_built_with_them(sims):
    """Issue 26 (several runs per launch): time back to 0, the noise of the new seed, the
    operator's new walk, the arms' speed scales as built."""
    rewound = sims(7, walk_seed=1)
    run(rewound)
    rewound.cell.arm_by_name["IRB140"].set_speed_scale(0.0)      # a monitor's last word
    rewind_simulation(rewound, 8, walk_seed=3)
    assert rewound.time_s == 0.0
    built = sims(8, walk_seed=3)
    assert rewound.cell.operator.state() == built.cell.operator.state()
    assert_identical(run(built), run(rewound))
    assert rewound.time_s == built.time_s


def test_a_walk_seed_without_an_operator_is_refused_and_changes_nothing(sims):
    sim = sims(7)
    sim.cell.operator = None
    sim.step()
    before = (sim.frame, sim.seed, sim.cell.laser_seed, sim.cell.kinect_seed)
    with pytest.raises(ValueError, match="no cell operator"):
        rewind_simulation(sim, 9, walk_seed=2)
    assert (sim.frame, sim.seed, sim.cell.laser_seed, sim.cell.kinect_seed) == before
