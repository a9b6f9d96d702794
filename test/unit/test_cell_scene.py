"""The cell section of scene files, the walking operator and V-REP's object matrices: pure
logic, no ROS, no pybullet."""
import math
import os

import numpy as np
import pytest

from epuck_vrep_compat.cell.devices.operator import WalkingOperator
from epuck_vrep_compat.cell.devices.operator_motion import PingPongPath
from epuck_vrep_compat.geometry.transforms import quat_rotate
from epuck_vrep_compat.scene.cell_file import parse_cell
from epuck_vrep_compat.scene.scene_file import SceneError, load_scene
from repo import REPO

WORLDS = os.path.join(REPO, "worlds")


def test_the_shipped_cell_parses_with_every_part():
    scene = load_scene(os.path.join(WORLDS, "merlin_cell.yaml"))
    cell = scene.cell
    assert [a.name for a in cell.arms] == ["IRB140", "SIX", "youBot"]
    assert all(os.path.isfile(a.urdf) for a in cell.arms)
    assert [p.name for p in cell.proximity] == [f"Proximity_sensor{k}" for k in range(10, 21)]
    assert all((p.min_range_m, p.max_range_m) == (0.02, 0.08) for p in cell.proximity)
    assert cell.laser.count == 682 and cell.laser.topic == "front_scan"
    # the URG-04LX-UG01's steps 44..725 of 1024, front = step 384
    step = 2.0 * math.pi / 1024.0
    assert cell.laser.angle_min_rad == pytest.approx((44 - 384) * step, abs=1e-6)
    assert cell.laser.angle_increment_rad == pytest.approx(step, abs=1e-9)
    assert [c.name for c in cell.cameras] == ["camera0", "camera"]
    assert all(c.resolution == (128, 128) and c.angle_rad == pytest.approx(math.radians(80))
               and (c.near_m, c.far_m) == (0.01, 3.0) for c in cell.cameras)
    assert cell.kinect.resolution == (640, 480)
    assert scene.arena.floor_name == "Plane"


def _cell(**overrides):
    d = {"robots": [], "operator": {"name": "Bill", "waypoints_m": [[0, 0], [1, 0]]}}
    d.update(overrides)
    return d


@pytest.mark.parametrize("data, key", [
    (_cell(robots=[{"name": "a", "urdf": "missing.urdf", "position_m": [0, 0, 0]}]), "urdf"),
    (_cell(operator={"name": "Bill", "waypoints_m": [[0, 0]]}), "waypoints_m"),
    (_cell(operator={"name": "Bill", "waypoints_m": [[0, 0], [1, 0]], "speed_m_s": -1}),
     "speed_m_s"),
    (_cell(proximity_sensors=[{"name": "p", "parent": "l", "position_m": [0, 0, 0],
                               "min_range_m": 0.08, "max_range_m": 0.02}]), "max_range_m"),
    (_cell(laser={"name": "h", "position_m": [0, 0, 0], "count": 0}), "count"),
    (_cell(cameras=[{"name": "c", "matrix": [1, 0, 0]}]), "matrix"),
    (_cell(cameras=[{"name": "c", "matrix": [0] * 12, "angle_deg": 190}]), "angle_deg"),
    (_cell(cameras=[{"name": "c", "matrix": [0] * 12, "blob_topics": ["x"]}]), "blob_topics"),
    (_cell(kinect={"position_m": [0, 0, 1], "near_m": 2, "far_m": 1}), "far_m"),
    (_cell(wheels=3), "wheels"),
])
def test_a_bad_cell_entry_is_named(data, key):
    with pytest.raises(SceneError, match=key):
        parse_cell(data, "cell", WORLDS)


def test_the_operator_walks_out_and_back_at_its_speed():
    spec = parse_cell(_cell(operator={"name": "Bill", "waypoints_m": [[0, 0], [2, 0], [2, 1]],
                                      "speed_m_s": 1.0}), "cell", WORLDS).operator
    walker = WalkingOperator(spec, PingPongPath(spec.waypoints_m, spec.speed_m_s))
    samples = []
    for k in range(80):              # 8 s at 0.1 s: 3 m out, 3 m back, 2 m out again
        walker.seek(0.1 * (k + 1))
        samples.append(walker.state())
    x, y, heading, outbound = samples[14]          # 1.5 m: on the first segment
    assert (x, y) == pytest.approx((1.5, 0.0)) and heading == pytest.approx(0.0) and outbound
    x, y, heading, outbound = samples[24]          # 2.5 m: on the second
    assert (x, y) == pytest.approx((2.0, 0.5)) and heading == pytest.approx(math.pi / 2)
    x, y, heading, outbound = samples[44]          # 4.5 m: coming back along the first
    assert (x, y) == pytest.approx((1.5, 0.0)) and not outbound
    assert abs(heading) == pytest.approx(math.pi)
    x, y, _, outbound = samples[79]                # 8 m: back at 2 m, out again
    assert (x, y) == pytest.approx((2.0, 0.0), abs=1e-9) and outbound
    steps = np.diff([s[:2] for s in samples], axis=0)
    assert np.hypot(steps[:, 0], steps[:, 1]).max() <= 0.1 + 1e-9


def test_a_vrep_matrix_becomes_the_same_pose():
    from epuck_vrep_compat.cell.devices.cell_sensors import pose_from_vrep_matrix
    # camera 1 of the thesis: x axis = first column, translation = fourth
    m = [-0.9983, 0.0558, 0.0183, 1.4507, 0.0543, 0.9956, -0.0770, 1.6420,
         -0.0225, -0.0759, -0.9969, 2.8738]
    position, quat = pose_from_vrep_matrix(m)
    assert position == pytest.approx((1.4507, 1.6420, 2.8738))
    r = np.asarray(m).reshape(3, 4)[:, :3]
    for axis in range(3):
        e = np.zeros(3)
        e[axis] = 1.0
        assert quat_rotate(quat, e) == pytest.approx(r[:, axis], abs=2e-3)
    assert np.linalg.norm(quat) == pytest.approx(1.0)


def test_the_robot_description_names_links_as_their_scene_objects():
    """rviz draws a robot from robot_description + TF: the description's links must be the TF
    frames, also when the world file renames the robot (its base link is the robot's name)."""
    import xml.etree.ElementTree as ET

    import pybullet as pb

    from epuck_vrep_compat.cell.devices.articulated import ArticulatedRobot
    from epuck_vrep_compat.scene.registry import SceneRegistry

    spec = parse_cell({"robots": [{"name": "left_arm", "urdf": "../models/irb140.urdf",
                                   "position_m": [0, 0, 0]}]}, "cell", WORLDS)
    client = pb.connect(pb.DIRECT)
    try:
        registry = SceneRegistry()
        arm = ArticulatedRobot(client, spec.arms[0], registry)
        root = ET.fromstring(arm.description())
    finally:
        pb.disconnect(client)
    links = {link.get("name") for link in root.iter("link")}
    assert root.get("name") == "left_arm"
    assert "left_arm" in links and "IRB140" not in links
    assert links == {obj.name for obj in arm.objects.values()}
    ends = {end.get("link") for joint in root.iter("joint")
            for end in (joint.find("parent"), joint.find("child"))}
    assert ends == links
    assert all(registry.handle_of(name) != -1 for name in links)
