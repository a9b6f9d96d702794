"""The supervisor's link speeds (``nodes/link_speeds.py``): the joints' part from the URDF,
plus a mobile base's own motion (issue 26: the youBot's base was ignored), and the root's
twist from two of its poses on TF."""
import math
import os

import numpy as np
import pytest

from epuck_vrep_compat.builder.build import build_simulation
from epuck_vrep_compat.geometry.transforms import IDENTITY_QUAT, compose, quat_from_yaw
from epuck_vrep_compat.nodes.link_speeds import LinkSpeeds, root_twist
from epuck_vrep_compat.scene.scene_file import load_scene
from repo import REPO


@pytest.fixture(scope="module")
def youbot():
    sim = build_simulation(load_scene(os.path.join(REPO, "worlds", "merlin_cell.yaml")))
    arm = sim.cell.arm_by_name["youBot"]
    yield LinkSpeeds(arm.description()), [j.name for j in arm.joints]
    sim.cell.close()


def points(kinematics):
    """A point 10 cm out on every link, and where it is in the root's frame at q = 0."""
    links = list(kinematics.chain.link_names)
    local = [np.array([0.1, 0.0, 0.0])] * len(links)
    poses = kinematics.chain.forward({})
    return links, local, poses


def test_at_rest_every_point_is_still(youbot):
    kinematics, names = youbot
    links, local, _ = points(kinematics)
    zeros = [0.0] * len(names)
    np.testing.assert_allclose(kinematics.speeds(names, zeros, zeros, links, local), 0.0,
                               atol=1e-9)


def test_the_base_translating_moves_every_point_at_its_speed(youbot):
    kinematics, names = youbot
    links, local, _ = points(kinematics)
    zeros = [0.0] * len(names)
    speeds = kinematics.speeds(names, zeros, zeros, links, local, [0.3, 0.4, 0.0], None)
    np.testing.assert_allclose(speeds, 0.5, atol=1e-9)


def test_the_base_turning_moves_each_point_at_its_distance_from_the_axis(youbot):
    kinematics, names = youbot
    links, local, poses = points(kinematics)
    zeros = [0.0] * len(names)
    speeds = kinematics.speeds(names, zeros, zeros, links, local, None, [0.0, 0.0, 2.0])
    for link, point, speed in zip(links, local, speeds):
        p, _ = compose(*poses[link], point, IDENTITY_QUAT)
        assert speed == pytest.approx(2.0 * math.hypot(p[0], p[1]), abs=1e-9)
    assert speeds.max() > 0.2                     # the arm reaches out from the base's axis


def test_the_joints_and_the_base_add_as_vectors(youbot):
    kinematics, names = youbot
    links, local, _ = points(kinematics)
    q = [0.0] * len(names)
    qd = [0.0] * len(names)
    qd[0] = 1.0                                   # the arm's first joint turns
    alone = kinematics.speeds(names, q, qd, links, local)
    moving = [i for i, s in enumerate(alone) if s > 0.01]
    assert moving
    with_base = kinematics.speeds(names, q, qd, links, local, [0.5, 0.0, 0.0], None)
    # |a + b| within | |a| - |b| | .. |a| + |b|, and not the joints' speed alone
    assert np.all(with_base <= alone + 0.5 + 1e-9)
    assert np.all(with_base >= np.abs(alone - 0.5) - 1e-9)
    assert not np.allclose(with_base[moving], alone[moving])


def test_root_twist_from_two_poses_is_in_the_roots_frame():
    before = (1.0, np.zeros(3), quat_from_yaw(math.pi / 2 - 0.1))
    after = (1.1, np.array([0.0, 0.05, 0.0]), quat_from_yaw(math.pi / 2))
    linear, angular = root_twist(before, after)
    np.testing.assert_allclose(linear, [0.5, 0.0, 0.0], atol=1e-9)   # forward, facing +y
    np.testing.assert_allclose(angular, [0.0, 0.0, 1.0], atol=1e-9)
    # across +-pi the yaw rate is the short way round
    _, angular = root_twist((0.0, np.zeros(3), quat_from_yaw(math.pi - 0.05)),
                            (0.1, np.zeros(3), quat_from_yaw(-math.pi + 0.05)))
    assert angular[2] == pytest.approx(1.0)
    # no time between them: at rest
    linear, angular = root_twist(after, after)
    assert not linear.any() and not angular.any()
