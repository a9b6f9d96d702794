"""/tf_static (no master): the e-pucks' and the cell's fixed frames leave the per-step /tf and
go, all parts in one latched message, to /tf_static; again only when they change."""
import os

import numpy as np
import pytest
from tf2_msgs.msg import TFMessage

from epuck_vrep_compat.builder.build import SimulationConfig, build_simulation
from epuck_vrep_compat.ros.cell.transforms import CellTransforms
from epuck_vrep_compat.ros.epuck.profiles import PROFILES
from epuck_vrep_compat.ros.epuck.transforms import TfFace
from epuck_vrep_compat.ros.transport.static_tf import StaticTransforms, static_transform
from epuck_vrep_compat.scene.scene_file import load_scene
from epuck_vrep_compat.sim.control import RUNNING, SimulationControl
from epuck_vrep_compat.vrep.backend import VrepBackend
from repo import REPO

WORLD = -1


class LatchedTopic:
    """Stands in for the latched rospy publisher: keeps what was published."""

    def __init__(self):
        self.messages = []

    def publish(self, msg):
        assert isinstance(msg, TFMessage)
        self.messages.append(msg)

    def children(self, k=-1):
        return [(t.header.frame_id, t.child_frame_id) for t in self.messages[k].transforms]


def test_parts_share_one_message_and_an_unchanged_part_is_not_resent():
    topic = LatchedTopic()
    static = StaticTransforms(topic)
    static.set("a", [static_transform("odom", "x", (1, 2, 3), (0, 0, 0, 1))])
    static.set("b", [static_transform("world", "odom", (0, 0, 0), (0, 0, 0, 1))])
    assert topic.children() == [("odom", "x"), ("world", "odom")]
    static.set("a", [static_transform("odom", "x", (1, 2, 3), (0, 0, 0, 1))])
    assert len(topic.messages) == 2
    static.set("a", [])
    assert topic.children() == [("world", "odom")]
    t = topic.messages[0].transforms[0].transform
    assert (t.translation.x, t.translation.y, t.translation.z, t.rotation.w) == (1, 2, 3, 1)


@pytest.mark.parametrize("profile, extra", [("vrep", []), ("epuck_driver", ["base_laser"])])
def test_epuck_fixed_frames_are_static_and_only_moving_ones_per_step(profile, extra):
    sim = build_simulation(load_scene(os.path.join(REPO, "test", "worlds", "empty.yaml")),
                           SimulationConfig([PROFILES[profile].robot_name(i) for i in range(2)]))
    topic = LatchedTopic()
    face = TfFace(PROFILES[profile], sim, StaticTransforms(topic))
    frame = PROFILES[profile].frame
    fixed = [f"base_prox{k}" for k in range(8)] + ["body_top", "camera_optical"] + extra
    for robot in sim.epucks.robot_names:
        base = frame(robot, "base_link")
        assert {(base, frame(robot, c)) for c in fixed} <= set(topic.children())
        assert {("odom", base), (base, frame(robot, "left_wheel")),
                (base, frame(robot, "right_wheel"))} <= set(face.frames)
    assert len(topic.children()) == 2 * len(fixed)
    assert len(face.frames) == 2 * 3
    message = face.message(1, 0)
    assert message is not None
    face.sync()                                    # nothing changed: nothing re-sent
    assert len(topic.messages) == 1
    sim.epucks.remove_robot(sim.epucks.robot_names[0])
    face.sync()
    assert len(topic.messages) == 2 and len(topic.children()) == len(fixed)


@pytest.fixture
def cell_sim():
    sim = build_simulation(load_scene(os.path.join(REPO, "worlds", "merlin_cell.yaml")))
    yield sim
    sim.cell.close()


def test_cell_mounts_are_static_and_resent_only_when_moved(cell_sim):
    topic = LatchedTopic()
    transforms = CellTransforms(cell_sim, StaticTransforms(topic))
    mounts = {"Hokuyo_URG_04LX_UG01_ROS", "camera0", "camera", "kinect_depth", "kinect_rgb"}
    static_children = {child for _, child in topic.children()}
    assert mounts <= static_children
    assert all(parent == "world" for parent, _ in topic.children())
    moving = {name for name, _ in transforms._moving_frames()}
    assert not moving & static_children
    assert {"IRB140", "Bill"} <= moving
    for _ in range(3):
        cell_sim.step()
        transforms.update_static(0, 0)
    assert len(topic.messages) == 1                # fixed mounts: sent once
    backend = VrepBackend(cell_sim, SimulationControl(cell_sim, RUNNING), real_time=True)
    camera = cell_sim.registry.handle_of("camera0")
    backend.set_pose(camera, WORLD, position=np.array([0.5, 0.5, 2.5]))
    transforms.update_static(0, 0)
    assert len(topic.messages) == 2
    moved = [t for t in topic.messages[-1].transforms if t.child_frame_id == "camera0"][0]
    assert (moved.transform.translation.x, moved.transform.translation.z) == (0.5, 2.5)
