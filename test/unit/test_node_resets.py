"""The client nodes' ``~reset`` (no master; rospy's parts stand-ins from :mod:`fake_ros`): a
node used for a walk and reset behaves as a node launched again, input for input, and its
reset restores what a run changes (filters, counts, latched messages, rospy's time, TF's
dynamic transforms; the static ones kept); the supervisor's handshake after a reset waits for
the operator as at its start, and only the last reset's handshake is sent."""
import threading
import types

import numpy as np
import pytest
import rospy
from geometry_msgs.msg import PoseWithCovarianceStamped, TransformStamped
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import LaserScan
from std_msgs.msg import Float32

import fake_ros
from epuck_vrep_compat.nodes import node_reset
from epuck_vrep_compat.nodes.operator_tracker import OperatorTracker
from epuck_vrep_compat.nodes.ssm_pacing import OperatorSteps, StepPacer
from epuck_vrep_compat.nodes.ssm_supervisor import SsmSupervisor
from epuck_vrep_compat.thesis.kinect import Kinect

# rospy's own time setter, which the resets call, uses a deprecated threading name
pytestmark = pytest.mark.filterwarnings("ignore:notifyAll:DeprecationWarning")

STEP_S = 0.05


def at(t):
    rospy.rostime._set_rostime(rospy.Time.from_sec(t))     # noqa: SLF001  the test's clock
    return rospy.Time.from_sec(t)


def transform(child, parent="world", z=0.3):
    msg = TransformStamped()
    msg.header.frame_id, msg.child_frame_id = parent, child
    msg.transform.translation.z, msg.transform.rotation.w = z, 1.0
    return msg


def walk(ros, tracker, shift, person=True, steps=20):
    """The tracker's estimates over a walk of blobs (``shift`` moves him) and laser scans (a
    person-sized cluster near him when ``person``, on a wall 8 m away)."""
    out = []
    for k in range(steps):
        now = at(STEP_S * (k + 1))
        for camera in range(2):
            for axis, value in (("X", 0.4 + shift + 0.002 * k), ("Y", 0.5)):
                ros.subscribers[f"/vrep/Blob_Camera_{camera}_{axis}"][0].deliver(Float32(value))
        scan = LaserScan(angle_min=-1.5, angle_increment=0.01)
        scan.header.frame_id, scan.header.stamp = "laser", now
        ranges = np.full(300, 8.0)
        if person:
            ranges[195 + k // 2:203 + k // 2] = 6.0
        scan.ranges = list(ranges)
        ros.subscribers["/vrep/front_scan"][0].deliver(scan)
        tracker.cycle(now=now)
        pose = tracker.pose_pub.sent[-1].pose
        out.append((pose.pose.position.x, pose.pose.position.y, tuple(pose.covariance)))
    return out


def test_a_tracker_reset_estimates_as_a_tracker_launched_again(monkeypatch):
    fresh_ros = fake_ros.install(monkeypatch)
    fresh = OperatorTracker()
    used_ros = fake_ros.install(monkeypatch)
    used = OperatorTracker()
    for tracker in (fresh, used):
        tracker.tf.set_transform_static(transform("laser"), "test")
    at(0.0)
    expected = walk(fresh_ros, fresh, 0.0)
    assert fresh.filter.started and len(set(expected)) == len(expected)
    assert walk(used_ros, used, 0.3, person=False) != expected     # another walk first
    used.reset()
    assert rospy.get_rostime() == rospy.Time(0)             # as before the first /clock
    assert used.tf.can_transform("world", "laser", rospy.Time(0))   # static: kept
    assert [t.shut for t in used_ros.timers] == [True, False]       # its timer from 0 again
    assert walk(used_ros, used, 0.0) == expected


def test_a_tracker_in_lock_step_forgets_its_steps_and_says_it_is_ready_again(monkeypatch):
    fake_ros.install(monkeypatch, {"lockstep": True})
    tracker = OperatorTracker()
    ready = tracker.pose_pub.sent[-1]
    assert ready.header.stamp.is_zero() and tracker.pose_pub.impl.latch is ready
    tracker.steps.gone.add("Hokuyo")
    tracker.steps.clock.last = rospy.Time(15)
    tracker.scan.put(LaserScan())
    tracker.reset()
    assert tracker.steps.gone == set() and tracker.steps.clock.last == rospy.Time(0)
    assert tracker.scan.take() is None and tracker.scan.frame_id == ""
    again = tracker.pose_pub.sent[-1]
    assert again is not ready and again.header.stamp.is_zero()
    assert tracker.pose_pub.impl.latch is again


def test_a_tracker_in_lock_step_waits_for_the_lasers_scan_of_time_0_at_the_first_step(
        monkeypatch):
    """The cell's laser scans at time 0 too (at a launch or a rewind) and sends that scan with
    the first step: that step waits for it, so whether it came in time changes no row; later
    steps wait at the laser's period only, and never for a Kinect image at the first."""
    fake_ros.install(monkeypatch, {"lockstep": True})
    tracker = OperatorTracker()
    steps = tracker.steps
    steps.get_signal = lambda _name: types.SimpleNamespace(result=0)
    waits = []
    for what, inbox in (("laser", tracker.scan), ("kinect", tracker.depth)):
        monkeypatch.setattr(inbox, "wait_for", lambda stamp, timeout_s=2.0, gone=None, w=what:
                            waits.append((w, round(stamp.to_sec(), 3), timeout_s)) or False)
    for k in range(1, 5):
        steps.step(rospy.Time.from_sec(STEP_S * k), rospy.Time.from_sec(STEP_S * (k - 1)))
    waited = [(w, t) for w, t, timeout_s in waits if timeout_s > 0.0]
    assert waited == [("laser", 0.05), ("laser", 0.1), ("kinect", 0.1), ("laser", 0.2),
                      ("kinect", 0.2)]


def supervisor_state(sup):
    channel = sup.channels["IRB140"]
    g = channel.governor
    return (sup.enabled, sup.operator, sup.cycle_s, sup._last_cycle, sup.pacer._last,
            g.scale, g.stopped, g.reference_speed_m_s, list(g._learnt), channel.joints,
            channel.kinematics, channel.root_pose, channel.root_velocity, channel.status,
            channel.status_pub.impl.latch, channel.command.impl.latch, channel.command.sent)


def handshakes_done():
    for thread in threading.enumerate():
        if thread.name == "ssm_handshake":
            thread.join()


def test_a_supervisor_reset_is_a_supervisor_launched_again(monkeypatch):
    params = {"robots": ["IRB140"], "lockstep": True}
    fake_ros.install(monkeypatch, params)
    fresh = SsmSupervisor()
    ros = fake_ros.install(monkeypatch, params)
    used = SsmSupervisor()
    channel = used.channels["IRB140"]
    ros.services["~set_enabled"](type("Req", (), {"data": False})())
    channel.governor.scale = 0.5
    channel.governor.learn_speed(2.0, 14.0)
    channel.report(1.2, 0.9, 0.5, "ok")
    channel.joints, channel.root_pose = object(), (15.0, None, None)
    used.operator, used.cycle_s, used._last_cycle = object(), 0.1, rospy.Time(15)
    used.pacer._last = rospy.Time(15)
    used.reset()
    handshakes_done()
    assert supervisor_state(used)[:-1] == supervisor_state(fresh)[:-1]
    assert channel.command.sent[-1] == 0.0 == channel.command.impl.latch     # ready again


def test_after_a_reset_the_handshake_waits_for_the_operator_and_only_the_last_is_sent():
    operator = OperatorSteps()
    command = fake_ros.FakePublisher(fake_ros.Ros({}), "/IRB140/speed_scale", latch=True)
    channel = type("Channel", (), {"joints_subscriber": fake_ros.FakeSubscriber(
        fake_ros.Ros({}), "/IRB140/joint_states"), "command": command})()
    pacer = StepPacer({"IRB140": channel}, None, None, operator)
    ready = PoseWithCovarianceStamped()
    operator.on_message(ready)
    for t in (0.05, 0.10):
        step = PoseWithCovarianceStamped()
        step.header.stamp = rospy.Time.from_sec(t)
        operator.on_message(step)
    assert operator.next().header.stamp.to_sec() == 0.05
    pacer.restart()
    pacer.restart()                   # a reset again before the operator was ready
    assert command.sent == []         # not before the operator is ready
    late = PoseWithCovarianceStamped()
    late.header.stamp = rospy.Time(15)
    operator.on_message(late)         # before the ready message: no step's
    operator.on_message(ready)
    handshakes_done()
    assert command.sent == [0.0]      # once: the first reset's handshake sends nothing
    first = PoseWithCovarianceStamped()
    first.header.stamp = rospy.Time.from_sec(0.05)
    operator.on_message(first)
    assert operator.next() is first   # counted from the ready message again


def test_a_kinect_reset_reads_at_the_steps_a_new_kinect_reads_at(monkeypatch):
    def steps_read(ros, kinect, clocks):
        read = []
        kinect.step = read.append
        for t in clocks:
            ros.subscribers["/clock"][0].deliver(Clock(clock=rospy.Time.from_sec(t)))
        return [round(stamp.to_sec(), 6) for stamp in read]

    clocks = [STEP_S * k for k in range(1, 21)]
    ros = fake_ros.install(monkeypatch, {"lockstep": True, "rate": 10.0})
    expected = steps_read(ros, Kinect(), clocks)
    assert expected == [round(0.1 * k, 6) for k in range(1, 11)]
    ros = fake_ros.install(monkeypatch, {"lockstep": True, "rate": 10.0})
    used = Kinect()
    steps_read(ros, used, [10.0 + t for t in clocks])
    used._clipping_checked = True
    answer = ros.services["~reset"](None)
    assert answer.success and not used._clipping_checked
    assert steps_read(ros, used, clocks) == expected


def test_a_reset_refused_says_why_and_counts_nothing(monkeypatch):
    ros = fake_ros.install(monkeypatch)
    calls = []

    def reset():
        calls.append(1)
        if len(calls) > 1:
            raise node_reset.ResetRefused("the camera is gone")
    service = node_reset.ResetService(reset)
    handler = ros.services["~" + "reset"]
    assert handler(None).success and service.count == 1
    answer = handler(None)
    assert (answer.success, answer.message, service.count) == (False, "the camera is gone", 1)


def test_ros_time_goes_back_to_0_only_in_simulated_time(monkeypatch):
    fake_ros.install(monkeypatch, {"use_sim_time": False})
    monkeypatch.setattr(rospy.rostime, "_rostime_current", None)      # wall time
    node_reset.restart_ros_time()
    assert rospy.get_rostime().to_sec() > 1e9
    fake_ros.install(monkeypatch)
    at(15.0)
    node_reset.restart_ros_time()
    assert rospy.get_rostime() == rospy.Time(0)


def test_tf_keeps_its_static_frames_and_forgets_the_runs(monkeypatch):
    fake_ros.install(monkeypatch)
    buffer = fake_ros.REAL_BUFFER(debug=False)
    listener = type("Listener", (), {"buffer": buffer, "last_update": rospy.Time(15),
                                     "last_update_lock": threading.Lock()})()
    buffer.set_transform_static(transform("laser"), "test")
    moving = transform("arm")
    moving.header.stamp = rospy.Time(15)
    buffer.set_transform(moving, "test")
    node_reset.clear_tf(listener)
    assert listener.last_update == rospy.Time(0)
    assert buffer.can_transform("world", "laser", rospy.Time(0))
    assert not buffer.can_transform("world", "arm", rospy.Time(0))
    moving.header.stamp = rospy.Time.from_sec(0.05)           # the new walk's, accepted
    buffer.set_transform(moving, "test")
    assert buffer.can_transform("world", "arm", rospy.Time.from_sec(0.05))
