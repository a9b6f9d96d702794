"""Nothing for nobody (no master): with no subscriber the e-puck faces pack, copy and render
nothing per step; one subscriber gets exactly its topic's work done."""
import os
import socket
import struct

import pytest
import rospy.core
from sensor_msgs.msg import Range
from tf2_msgs.msg import TFMessage

from epuck_vrep_compat.builder.build import SimulationConfig, build_simulation
from epuck_vrep_compat.epuck.cameras import render_robot_cameras
from epuck_vrep_compat.ros.epuck import camera as camera_module
from epuck_vrep_compat.ros.epuck.camera import CameraFace
from epuck_vrep_compat.ros.epuck.profiles import PROFILES
from epuck_vrep_compat.ros.epuck.sensors import EpuckFace
from epuck_vrep_compat.ros.epuck.transforms import TfFace
from epuck_vrep_compat.ros.face import Step
from epuck_vrep_compat.ros.transport import wire
from epuck_vrep_compat.ros.transport.static_tf import StaticTransforms
from epuck_vrep_compat.ros.transport.step_batch import StepBatch, synchronous_publisher
from epuck_vrep_compat.scene.scene_file import load_scene
from repo import REPO

PROFILE = PROFILES["vrep"]


class Subscriber:
    """A connection as rospy's publisher sees one; keeps what it is sent."""

    opened = []

    def __init__(self, name):
        Subscriber.opened.append(self)
        self.endpoint_id = name
        self.done = False
        self.stat_bytes = 0
        self.written = []
        self.socket, self._peer = socket.socketpair()    # rospy polls the descriptor
        self.cleanup_cb = None

    def set_cleanup_callback(self, callback):
        self.cleanup_cb = callback

    def write_data(self, data):
        self.written.append(data)

    def fileno(self):
        return self.socket.fileno()

    def close(self):
        """Done, as rospy's transport: its cleanup callback ends rospy's queue thread."""
        self.done = True
        if self.cleanup_cb is not None:
            self.cleanup_cb(self)


class Ignored:
    def publish(self, msg):
        pass


@pytest.fixture
def faces(monkeypatch):
    # rospy refuses publishers before init_node; with no master there is nothing to register
    # with (no registration listener), so the publishers work locally, as the faces need
    monkeypatch.setattr(rospy.core, "_client_ready", True)
    sim = build_simulation(load_scene(os.path.join(REPO, "test", "worlds", "empty.yaml")),
                           SimulationConfig([PROFILE.robot_name(i) for i in range(2)]))
    work = []
    for kind, method in (("MessageBatch", "pack_view"),           # every per-step packing
                         ("TransformBatchWire", "frame")):
        cls = getattr(wire, kind)
        original = getattr(cls, method)
        monkeypatch.setattr(cls, method, lambda self, *a, _o=original, _k=kind, **kw:
                            (work.append(_k), _o(self, *a, **kw))[1])

    def render(epuck_robots, robot_names, *args, **kwargs):
        work.append(("render", tuple(robot_names)))
        return render_robot_cameras(epuck_robots, robot_names, *args, **kwargs)
    monkeypatch.setattr(camera_module, "render_robot_cameras", render)
    epucks = EpuckFace(PROFILE, sim, "si", "ros", True)
    tf = TfFace(PROFILE, sim, StaticTransforms(Ignored()))
    cameras = CameraFace(PROFILE, sim)
    tf_pub = synchronous_publisher("/test_idle_faces/tf", TFMessage)
    yield sim, (epucks, tf, cameras), work, tf_pub
    while Subscriber.opened:
        Subscriber.opened.pop().close()
    for robot in epucks.robots:
        robot.close()
    for camera in cameras._cameras.values():
        camera.close()


def step_once(sim, faces, tf_pub):
    sim.step()
    batch = StepBatch()
    step = Step(1, 0, batch, tf_pub)
    for face in faces:
        face.publish(step)
    return batch


def test_nobody_subscribed_means_no_packing_and_no_rendering(faces):
    sim, all_faces, work, tf_pub = faces
    for _ in range(3):
        batch = step_once(sim, all_faces, tf_pub)
        assert batch._pending == {}
    assert work == []


def test_one_subscriber_gets_only_its_topics_work(faces):
    sim, (epucks, tf, cameras), work, tf_pub = faces
    ranges = Subscriber("/ranges")
    epucks.robots[1].ranges[2].impl.add_connection(ranges)
    camera = cameras._cameras[sim.epucks.robot_names[0]]
    camera.image.impl.add_connection(Subscriber("/viewer"))
    batch = step_once(sim, (epucks, tf, cameras), tf_pub)
    # the ranges of all robots packed once (one array op), one camera rendered, no /tf
    first = sim.epucks.robot_names[0]
    assert sorted(work, key=str) == sorted(["MessageBatch", ("render", (first,))], key=str)
    # both go out through the step batch (the camera's image too, off the interpreter); the
    # ranges as slices of their packed step, straight to the writer
    assert set(batch._pending) == {camera.image.impl}
    batch.flush()
    frame = ranges._peer.recv(1 << 16, socket.MSG_DONTWAIT)
    (size,) = struct.unpack("<I", frame[:4])
    assert size == len(frame) - 4
    msg = Range().deserialize(frame[4:])
    assert msg.header.frame_id == PROFILE.frame(sim.epucks.robot_names[1], "base_prox2")
    assert msg.range == pytest.approx(min(max(sim.epucks.swarm.ranges[1, 2], msg.min_range),
                                          msg.max_range))
