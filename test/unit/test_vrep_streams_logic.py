"""The /vrep streams without a master: naming, sanitising, reference counting, what each stream
publishes and what each subscriber does, with the rospy side replaced by a fake."""
import math
import os
import struct
import threading

import numpy as np
import pytest
import rospy
from geometry_msgs.msg import Point, Twist
from sensor_msgs.msg import Joy
from std_msgs.msg import Float32, Float64, Int32, UInt8
from vrep_common.msg import JointSetStateData
from vrep_common.srv import (
    simRosDisablePublisherRequest, simRosDisableSubscriberRequest, simRosEnablePublisherRequest,
    simRosEnableSubscriberRequest)

from epuck_vrep_compat.builder.build import SimulationConfig, build_simulation
from epuck_vrep_compat.compat import vrep_codes as vc
from epuck_vrep_compat.ros.vrep_plugin.stream_names import (
    Aux, FrameNames, resolve_topic, sanitize, stream_identity, unique_topic_name)
from epuck_vrep_compat.ros.vrep_plugin.stream_subscribers import RawString
from epuck_vrep_compat.ros.vrep_plugin.streams import VrepStreams
from epuck_vrep_compat.scene.scene_file import load_scene
from epuck_vrep_compat.sim.control import RUNNING, STOPPED, SimulationControl
from epuck_vrep_compat.vrep.backend import VrepBackend
from repo import REPO

WORLDS = os.path.join(REPO, "test", "worlds")


# --- pure naming ---------------------------------------------------------------------------
def test_sanitize_and_resolve():
    assert sanitize("a#0-(b)") == "a_HASHMARK_0_MINUSMARK__OPARENTHESISMARK_b_CPARENTHESISMARK_"
    assert resolve_topic("prox") == "/vrep/prox"
    assert resolve_topic("/abs/prox") == "/abs/prox"


def test_unique_names_append_2_as_vrep():
    taken = {"/vrep/a", "/vrep/a_2"}
    assert unique_topic_name("a", taken.__contains__) == "a_2_2"
    assert unique_topic_name("info", lambda _: False) == "info_2"
    assert unique_topic_name("/vrep/info", lambda _: False) == "/vrep/info_2"
    assert unique_topic_name("x#1", lambda _: False) == "x_HASHMARK_1"


def test_stream_identity_by_command_group():
    a, b = Aux(1, 2, "s"), Aux(1, 3, "t")
    assert stream_identity(vc.STRMCMD_GET_OBJECT_SELECTION, a) == \
        stream_identity(vc.STRMCMD_GET_OBJECT_SELECTION, b)
    assert stream_identity(vc.STRMCMD_GET_JOINT_STATE, a) == \
        stream_identity(vc.STRMCMD_GET_JOINT_STATE, b)              # auxInt1 only
    assert stream_identity(vc.STRMCMD_GET_OBJECT_POSE, a) != \
        stream_identity(vc.STRMCMD_GET_OBJECT_POSE, b)              # auxInt1 + auxInt2
    assert stream_identity(vc.STRMCMD_GET_TRANSFORM, Aux(1, 2, "x%y")) == \
        stream_identity(vc.STRMCMD_GET_TRANSFORM, Aux(1, 2, ""))     # the string is no identity
    assert stream_identity(vc.STRMCMD_GET_FLOAT_SIGNAL, Aux(1, 2, "s")) == \
        stream_identity(vc.STRMCMD_GET_FLOAT_SIGNAL, Aux(5, 6, "s"))
    assert stream_identity(vc.STRMCMD_GET_TWIST_STATUS, a) != \
        stream_identity(vc.STRMCMD_GET_TWIST_STATUS, Aux(1, 2, "t"))


def test_frame_ids_and_transform_renames():
    frames = FrameNames()
    assert frames.frame_id("ePuck_leftJoint#0") == "/ePuck_leftJoint_HASHMARK_0"
    assert frames.frame_id("/abs") == "/abs"
    assert frames.transform_frames("child", "world", "") == ("/child", "/world")
    assert frames.transform_frames("child", "parent", "c%p") == ("/c", "/p")
    assert frames.frame_id("child") == "/c" and frames.frame_id("parent") == "/p"
    assert frames.transform_frames("k", "w", "%q") == ("/k", "/q")
    assert frames.transform_frames("k2", "w2", "only") == ("/only", "/w2")
    assert frames.transform_frames("k3", "w3", "c3%") == ("/c3", "/w3")
    frames.clear()
    assert frames.frame_id("child") == "/child"


# --- the streams over a real simulation, rospy faked -----------------------------------------
class FakeTopic:
    def __init__(self, name, msg_class, callback=None, args=None):
        self.name, self.msg_class, self.callback, self.args = name, msg_class, callback, args
        self.registered = True

    def unregister(self):
        self.registered = False

    def deliver(self, msg):
        self.callback(msg, self.args)


class FakeWiring:
    def __init__(self):
        self.publishers, self.subscribers = [], []

    def advertise(self, resolved, msg_class):
        self.publishers.append(FakeTopic(resolved, msg_class))
        return self.publishers[-1]

    def subscribe(self, resolved, msg_class, callback, args, queue_size):
        self.subscribers.append(FakeTopic(resolved, msg_class, callback, args))
        return self.subscribers[-1]

    def publication_exists(self, resolved):
        return resolved in ("/tf", "/clock")

    def subscription_type(self, resolved):
        return "geometry_msgs/Twist" if resolved == "/ePuck0/cmd_vel" else None

    @staticmethod
    def is_legal(resolved):
        return " " not in resolved


class FakeBatch:
    def __init__(self):
        self.sent = []

    @staticmethod
    def wanted(pub):
        return True

    def add(self, pub, msg):
        self.sent.append((pub.name, msg))

    def on(self, topic):
        return [m for name, m in self.sent if name == topic]


@pytest.fixture
def vrep():
    rospy.rostime.set_rostime_initialized(True)      # rospy's log throttling reads the time
    sim = build_simulation(load_scene(os.path.join(WORLDS, "wall.yaml")),
                           SimulationConfig(["ePuck0"], seed=1))
    control = SimulationControl(sim, RUNNING)
    backend = VrepBackend(sim, control, real_time=False)
    wiring = FakeWiring()
    streams = VrepStreams(backend, threading.RLock(), wiring)
    control.listeners.append(lambda state: state == STOPPED and streams.remove_all())
    return backend, streams, wiring


def pub_req(name, cmd, a1=0, a2=0, s=""):
    return simRosEnablePublisherRequest(name, 1, cmd, a1, a2, s)


def sub_req(name, cmd, a1=0, a2=0, s=""):
    return simRosEnableSubscriberRequest(name, 1, cmd, a1, a2, s)


def step(backend, streams, batch=None):
    backend.sim.step()
    batch = batch or FakeBatch()
    t = rospy.Time.from_sec(backend.sim.time_s)
    streams.publish(batch, t.secs, t.nsecs)
    return batch


def test_reference_counting_and_name_collision(vrep):
    backend, streams, wiring = vrep
    left = backend.object_handle("ePuck_leftJoint")
    right = backend.object_handle("ePuck_rightJoint")
    assert streams.enable_publisher(pub_req("js", vc.STRMCMD_GET_JOINT_STATE, left)) \
        .effectiveTopicName == "js"
    # same command and aux: same topic, whatever name is asked, one more reference
    assert streams.enable_publisher(pub_req("other", vc.STRMCMD_GET_JOINT_STATE, left, 9)) \
        .effectiveTopicName == "js"
    assert streams.enable_publisher(pub_req("js", vc.STRMCMD_GET_JOINT_STATE, right)) \
        .effectiveTopicName == "js_2"
    assert streams.enable_publisher(pub_req("info", vc.STRMCMD_GET_JOINT_STATE, -2)) \
        .effectiveTopicName == "info_2"
    assert streams.enable_publisher(pub_req("/tf", vc.STRMCMD_GET_OBJECTS, -2)) \
        .effectiveTopicName == "/tf_2"
    assert [p.name for p in wiring.publishers] == ["/vrep/js", "/vrep/js_2", "/vrep/info_2",
                                                   "/tf_2"]
    disable = streams.disable_publisher
    assert disable(simRosDisablePublisherRequest("js")).referenceCounter == 1
    assert wiring.publishers[0].registered
    assert disable(simRosDisablePublisherRequest("js")).referenceCounter == 0
    assert not wiring.publishers[0].registered
    assert disable(simRosDisablePublisherRequest("js")).referenceCounter == -1
    assert any("could not be unpublished" in e for e in backend.errors.take())


def test_failures_return_vrep_values_and_record_errors(vrep):
    backend, streams, wiring = vrep
    enable = streams.enable_publisher
    assert enable(pub_req("", vc.STRMCMD_GET_JOINT_STATE, -2)).effectiveTopicName == ""
    assert enable(pub_req("x", vc.STRMCMD_READ_FORCE_SENSOR, 1)).effectiveTopicName == ""
    assert enable(pub_req("x", vc.STRMCMD_SET_JOINT_STATE)).effectiveTopicName == ""
    assert enable(pub_req("x", vc.STRMCMD_GET_JOINT_STATE, 99999)).effectiveTopicName == ""
    assert enable(pub_req("a b", vc.STRMCMD_GET_JOINT_STATE, -2)).effectiveTopicName == ""
    errors = backend.errors.take()
    assert errors[0] == "simRosEnablePublisher: Invalid topic name."
    assert all(e.startswith("simRosEnablePublisher: Topic could not be published.")
               for e in errors[1:4])
    assert streams.enable_subscriber(sub_req("w", vc.STRMCMD_GET_JOINT_STATE)).subscriberID == -1
    assert streams.enable_subscriber(sub_req("/ePuck0/cmd_vel", vc.STRMCMD_SET_JOINT_STATE)) \
        .subscriberID == -1
    assert streams.disable_subscriber(simRosDisableSubscriberRequest(7)).result == 0
    backend.control.stop()
    assert enable(pub_req("js", vc.STRMCMD_GET_JOINT_STATE, -2)).effectiveTopicName == ""
    assert streams.enable_subscriber(sub_req("w", vc.STRMCMD_SET_JOINT_STATE)).subscriberID == -1
    assert wiring.publishers == [] and wiring.subscribers == []


def test_joint_state_pose_and_proximity_content(vrep):
    backend, streams, _ = vrep
    left = backend.object_handle("ePuck_leftJoint")
    root = backend.object_handle("ePuck")
    sensor = backend.object_handle("ePuck_proxSensor3")      # looks backwards: nothing there
    front = backend.object_handle("ePuck_proxSensor0")       # the wall is 1.5 cm ahead
    streams.enable_publisher(pub_req("js", vc.STRMCMD_GET_JOINT_STATE, -2))
    streams.enable_publisher(pub_req("pose", vc.STRMCMD_GET_OBJECT_POSE, root, -1, "map"))
    streams.enable_publisher(pub_req("back", vc.STRMCMD_READ_PROXIMITY_SENSOR, sensor))
    streams.enable_publisher(pub_req("front", vc.STRMCMD_READ_PROXIMITY_SENSOR, front))
    backend.joint_command(left, "target_velocity", 2.0)
    batch = step(backend, streams)
    (joints,) = batch.on("/vrep/js")
    assert joints.name == ["ePuck_leftJoint", "ePuck_rightJoint"]
    assert joints.velocity == pytest.approx([2.0, 0.0], abs=0.1) and joints.header.seq == 1
    (pose,) = batch.on("/vrep/pose")
    assert pose.header.frame_id == "map" and pose.header.seq == 1
    assert pose.pose.position.x == pytest.approx(backend.pose(root)[0][0])
    assert batch.on("/vrep/back") == []
    (prox,) = batch.on("/vrep/front")
    assert 0.0 < prox.detectedPoint.z < 0.05 and prox.detectedObject.data > 0


def test_transforms_vision_and_signals(vrep):
    backend, streams, wiring = vrep
    camera = backend.object_handle("ePuck_camera")
    joint = backend.object_handle("ePuck_leftJoint")
    streams.enable_publisher(pub_req("tf1", vc.STRMCMD_GET_TRANSFORM, joint, vc.HANDLE_PARENT))
    streams.enable_publisher(pub_req("tf2", vc.STRMCMD_GET_TRANSFORM, camera, -1, "cam%map"))
    streams.enable_publisher(pub_req("img", vc.STRMCMD_GET_VISION_SENSOR_IMAGE, camera))
    streams.enable_publisher(pub_req("info", vc.STRMCMD_GET_VISION_SENSOR_INFO, camera))
    streams.enable_publisher(pub_req("cloud", vc.STRMCMD_GET_DEPTH_SENSOR_DATA, camera))
    streams.enable_publisher(pub_req("depth", vc.STRMCMD_GET_VISION_SENSOR_DEPTH_BUFFER, camera))
    streams.enable_publisher(pub_req("sig", vc.STRMCMD_GET_INTEGER_SIGNAL, 0, 0, "s"))
    streams.enable_publisher(pub_req("str", vc.STRMCMD_GET_AND_CLEAR_STRING_SIGNAL, 0, 0, "b"))
    assert [p.name for p in wiring.publishers][0] == "/tf"
    batch = step(backend, streams)
    (tf,) = batch.on("/tf")
    assert [(t.header.frame_id, t.child_frame_id) for t in tf.transforms] == \
        [("/ePuck", "/ePuck_leftJoint"), ("/map", "/cam")]
    width, height = backend.vision(camera).resolution
    (image,) = batch.on("/vrep/img")
    assert image.header.frame_id == "/cam"          # renamed by the transform stream
    assert (image.width, image.height, image.encoding, image.step) == \
        (width, height, "rgb8", 3 * width)
    (info,) = batch.on("/vrep/info_2")
    assert info.K[2] == width // 2 and info.P[10] == 1.0
    (cloud,) = batch.on("/vrep/cloud")
    assert (cloud.width, cloud.height, cloud.point_step) == (width, height, 16)
    assert len(cloud.data) == 16 * width * height
    z = np.frombuffer(cloud.data, dtype="<f4").reshape(-1, 4)[:, 2]
    assert np.all(z > 0.0)
    (depth,) = batch.on("/vrep/depth")
    assert (depth.x.data, depth.y.data, len(depth.data.data)) == (width, height, width * height)
    assert batch.on("/vrep/sig") == [] and batch.on("/vrep/str") == []
    backend.set_signal("int", "s", 42)
    backend.set_signal("string", "b", b"\x00\xff")
    batch = step(backend, streams)
    assert batch.on("/vrep/sig")[0].data == 42
    assert batch.on("/vrep/str")[0]._bytes == b"\x02\x00\x00\x00\x00\xff"
    assert step(backend, streams).on("/vrep/str") == []      # cleared after publishing


def test_group_data_selection_and_vision_read(vrep):
    backend, streams, _ = vrep
    camera = backend.object_handle("ePuck_camera")
    streams.enable_publisher(pub_req("names", vc.STRMCMD_GET_OBJECT_GROUP_DATA,
                                     vc.OBJECT_JOINT, vc.GROUP_DATA_NAMES))
    streams.enable_publisher(pub_req("empty", vc.STRMCMD_GET_OBJECT_GROUP_DATA,
                                     vc.OBJECT_FORCE_SENSOR, vc.GROUP_DATA_NAMES))
    streams.enable_publisher(pub_req("sel", vc.STRMCMD_GET_OBJECT_SELECTION))
    streams.enable_publisher(pub_req("read", vc.STRMCMD_READ_VISION_SENSOR, camera))
    backend.set_selection([camera])
    batch = step(backend, streams)
    (names,) = batch.on("/vrep/names")
    assert names.stringData.data == "ePuck_leftJoint\0ePuck_rightJoint\0"
    assert names.handles.data == backend.joints()
    assert batch.on("/vrep/empty") == []                 # an empty group ends the stream
    assert streams.disable_publisher(simRosDisablePublisherRequest("empty")).referenceCounter \
        == -1
    assert batch.on("/vrep/sel")[0].data == [camera]
    (read,) = batch.on("/vrep/read")
    assert read.triggerState.data == 0 and read.packetSizes.data == [15]
    assert len(read.packetData.data) == 15


def test_signal_fed_sensor_streams_and_parameters(vrep):
    backend, streams, _ = vrep
    root = backend.object_handle("ePuck")
    streams.enable_publisher(pub_req("scan", vc.STRMCMD_GET_LASER_SCANNER_DATA, root, 0, "l"))
    streams.enable_publisher(pub_req("cloud", vc.STRMCMD_GET_RANGE_FINDER_DATA, root, 0, "r"))
    streams.enable_publisher(pub_req("odom", vc.STRMCMD_GET_ODOM_DATA, root, -1))
    streams.enable_publisher(pub_req("twist", vc.STRMCMD_GET_TWIST_STATUS, root))
    streams.enable_publisher(pub_req("tws", vc.STRMCMD_GET_TWIST_STATUS, root, 0, "t"))
    streams.enable_publisher(pub_req("dt", vc.STRMCMD_GET_FLOATING_PARAMETER,
                                     vc.FLOATPARAM_SIMULATION_TIME_STEP))
    camera = backend.object_handle("ePuck_camera")
    streams.enable_publisher(pub_req("resx", vc.STRMCMD_GET_OBJECT_INT_PARAMETER, camera,
                                     vc.VISIONINTPARAM_RESOLUTION_X))
    assert streams.enable_publisher(pub_req("no", vc.STRMCMD_GET_INTEGER_PARAMETER, 12345)) \
        .effectiveTopicName == ""
    backend.set_signal("string", "l", struct.pack("<5f", 1.0, 2.0, -0.5, 0.5, 0.5))
    backend.set_signal("string", "r", struct.pack("<6f", 1, 2, 3, 4, 5, 6))
    batch = step(backend, streams)
    (scan,) = batch.on("/vrep/scan")
    assert list(scan.ranges) == [1.0, 2.0]
    assert (scan.angle_min, scan.angle_max, scan.range_max) == (-0.5, 0.5, 60.0)
    assert scan.header.frame_id == "/ePuck"
    (cloud,) = batch.on("/vrep/cloud")
    assert (cloud.width, cloud.height, cloud.point_step, cloud.row_step) == (2, 1, 12, 24)
    (odom,) = batch.on("/vrep/odom")
    assert (odom.header.frame_id, odom.child_frame_id) == ("/world", "/ePuck")
    assert batch.on("/vrep/twist")[0].header.frame_id == "/ePuck"
    assert batch.on("/vrep/tws") == []          # its signal is absent: the stream ended
    assert batch.on("/vrep/dt")[0].data == pytest.approx(0.05)
    assert batch.on("/vrep/resx")[0].data == backend.vision(camera).resolution[0]


def test_subscribers_that_fail_shut_down_as_the_plugin(vrep):
    backend, streams, wiring = vrep
    streams.enable_subscriber(sub_req("dt", vc.STRMCMD_SET_FLOATING_PARAMETER, 12345))
    streams.enable_subscriber(sub_req("joy", vc.STRMCMD_SET_JOY_SENSOR, 2, 1, "j"))
    streams.enable_subscriber(sub_req("bad_joy", vc.STRMCMD_SET_JOY_SENSOR, 0, 0, "k"))
    free = backend.sim.registry.add("free", vc.OBJECT_DUMMY)
    streams.enable_subscriber(sub_req("move", vc.STRMCMD_SET_OBJECT_POSITION, free.handle, -1))
    dt, joy, bad_joy, move = wiring.subscribers
    dt.deliver(Float32(0.1))
    assert not dt.registered                             # the parameter cannot be set
    joy.deliver(Joy(axes=[0.5], buttons=[1, 0]))
    assert struct.unpack("<3f", backend.signal("string", "j")) == (0.5, 0.0, 1.0)
    bad_joy.deliver(Joy())
    assert not bad_joy.registered and joy.registered
    move.deliver(Point(math.nan, 0.0, 0.0))              # ignored, the target is fine
    assert move.registered
    backend.sim.registry.remove(free.handle)
    move.deliver(Point(0.3, 0.0, 0.0))
    assert not move.registered


def test_a_stream_whose_target_goes_ends(vrep):
    backend, streams, _ = vrep
    free = backend.sim.registry.add("free", vc.OBJECT_DUMMY)
    streams.enable_publisher(pub_req("parent", vc.STRMCMD_GET_OBJECT_PARENT, free.handle))
    assert step(backend, streams).on("/vrep/parent")[0].data == -1
    backend.sim.registry.remove(free.handle)
    assert step(backend, streams).on("/vrep/parent") == []
    assert streams.disable_publisher(simRosDisablePublisherRequest("parent")).referenceCounter \
        == -1


def test_streams_on_a_removed_robot_end_and_the_step_goes_on(vrep):
    backend, streams, wiring = vrep
    parts = backend.sim.epucks.add_robot()                      # as simRosLoadModel does
    joint, sensor = parts.handle("leftJoint"), parts.handle("proxSensor0")
    streams.enable_publisher(pub_req("js", vc.STRMCMD_GET_JOINT_STATE, joint))
    streams.enable_publisher(pub_req("pose", vc.STRMCMD_GET_OBJECT_POSE, parts.root.handle, -1))
    streams.enable_subscriber(sub_req("v", vc.STRMCMD_SET_JOINT_TARGET_VELOCITY, joint))
    streams.enable_publisher(pub_req("prox", vc.STRMCMD_READ_PROXIMITY_SENSOR, sensor))
    batch = step(backend, streams)
    assert len(batch.on("/vrep/js")) == 1 and len(batch.on("/vrep/pose")) == 1
    backend.remove_object(parts.root.handle)
    batch = step(backend, streams)
    assert batch.sent == []                              # every stream ended, no exception
    wiring.subscribers[-1].deliver(Float64(1.0))
    assert not wiring.subscribers[-1].registered
    errors = backend.errors.take()
    assert sum("ended" in e for e in errors) == 3, errors
    assert streams.disable_publisher(simRosDisablePublisherRequest("js")).referenceCounter == -1


def test_subscribers(vrep):
    backend, streams, wiring = vrep
    left = backend.object_handle("ePuck_leftJoint")
    right = backend.object_handle("ePuck_rightJoint")
    ids = [streams.enable_subscriber(sub_req("/n/wheels", vc.STRMCMD_SET_JOINT_STATE))
           .subscriberID,
           streams.enable_subscriber(sub_req("si", vc.STRMCMD_SET_INTEGER_SIGNAL, 0, 0, "k"))
           .subscriberID,
           streams.enable_subscriber(sub_req("tw", vc.STRMCMD_SET_TWIST_COMMAND, 0, 0, "t"))
           .subscriberID,
           streams.enable_subscriber(sub_req("s#", vc.STRMCMD_APPEND_STRING_SIGNAL, 0, 0, "a"))
           .subscriberID,
           streams.enable_subscriber(sub_req("v", vc.STRMCMD_SET_JOINT_TARGET_VELOCITY, right))
           .subscriberID,
           streams.enable_subscriber(sub_req("p", vc.STRMCMD_SET_OBJECT_POSITION,
                                             backend.object_handle("ePuck"), -1)).subscriberID,
           streams.enable_subscriber(sub_req("c", vc.STRMCMD_CLEAR_INTEGER_SIGNAL, 0, 0, "k"))
           .subscriberID]
    assert ids == list(range(7))
    wheels, signal, twist, append, velocity, position, clear = wiring.subscribers
    assert append.name == "/vrep/s_HASHMARK_" and append.msg_class is RawString
    msg = JointSetStateData()
    msg.handles.data, msg.setModes.data, msg.values.data = [left, right], [2, 2], [1.5, -1.0]
    wheels.deliver(msg)
    np.testing.assert_allclose(backend.sim.epucks.command.wheel_rad_s[0], [1.5, -1.0])
    msg.values.data = [math.nan, 1.0]
    wheels.deliver(msg)
    msg.values.data = [1.0]
    wheels.deliver(msg)
    np.testing.assert_allclose(backend.sim.epucks.command.wheel_rad_s[0], [1.5, -1.0])
    assert len(backend.errors.take()) == 2
    velocity.deliver(Float64(0.5))
    assert backend.sim.epucks.command.wheel_rad_s[0, 1] == 0.5
    signal.deliver(Int32(7))
    assert backend.signal("int", "k") == 7
    clear.deliver(UInt8(0))
    assert backend.signals["int"] == {}
    twist.deliver(Twist())
    assert backend.signal("string", "t") == bytes(24)
    append.deliver(RawString(b"ab"))
    append.deliver(RawString(b"\xff"))
    assert backend.signal("string", "a") == b"ab\xff"
    position.deliver(Point(0.1, 0.05, 0.0))
    np.testing.assert_allclose(backend.pose(backend.object_handle("ePuck"))[0][:2], [0.1, 0.05])
    assert streams.disable_subscriber(simRosDisableSubscriberRequest(0)).result == 1
    assert not wheels.registered
    msg.values.data = [3.0, 3.0]
    wheels.deliver(msg)                                  # rospy may still deliver one: ignored
    np.testing.assert_allclose(backend.sim.epucks.command.wheel_rad_s[0], [1.5, 0.5])
    backend.control.stop()
    assert not any(s.registered for s in wiring.subscribers)
    backend.control.start()
    assert streams.enable_subscriber(sub_req("w", vc.STRMCMD_SET_JOINT_STATE)).subscriberID == 7


def test_raw_string_keeps_bytes():
    data = struct.pack("<I", 3) + b"\x00\xfe\x01"
    assert RawString().deserialize(data).data == b"\x00\xfe\x01"


def test_stream_tables_are_bounded(vrep, monkeypatch):
    """Issue 27: at most MAX_STREAMS publisher and subscriber streams at once; one more is
    refused with V-REP's failure value and the reason in the error log, and disabling one makes
    room again."""
    import epuck_vrep_compat.ros.vrep_plugin.streams as streams_module
    backend, streams, wiring = vrep
    monkeypatch.setattr(streams_module, "MAX_STREAMS", 3)
    names = [streams.enable_publisher(pub_req(f"s{k}", vc.STRMCMD_GET_FLOAT_SIGNAL, s=f"s{k}"))
             .effectiveTopicName for k in range(4)]
    assert names == ["s0", "s1", "s2", ""]
    assert backend.errors.take()[-1] == ("simRosEnablePublisher: Topic could not be published. "
                                         "(the stream table is full: 3 publisher streams are "
                                         "enabled; disable one first)")
    # another reference to a stream there is no new stream
    assert streams.enable_publisher(pub_req("x", vc.STRMCMD_GET_FLOAT_SIGNAL, s="s1")) \
        .effectiveTopicName == "s1"
    assert streams.disable_publisher(simRosDisablePublisherRequest("s0")).referenceCounter == 0
    assert streams.enable_publisher(pub_req("s3", vc.STRMCMD_GET_FLOAT_SIGNAL, s="s3")) \
        .effectiveTopicName == "s3"
    ids = [streams.enable_subscriber(sub_req(f"i{k}", vc.STRMCMD_SET_INTEGER_SIGNAL, s=f"i{k}"))
           .subscriberID for k in range(4)]
    assert ids == [0, 1, 2, -1]
    assert "3 subscriber streams are enabled" in backend.errors.take()[-1]
    assert streams.disable_subscriber(simRosDisableSubscriberRequest(1)).result == 1
    assert streams.enable_subscriber(sub_req("i4", vc.STRMCMD_SET_INTEGER_SIGNAL, s="i4")) \
        .subscriberID == 3
