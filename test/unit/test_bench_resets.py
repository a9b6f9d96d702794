"""The safety benchmark's own nodes' ``~reset`` (experiments/safety_ssm/ssm_bench/scripts; no
master, rospy's parts stand-ins from :mod:`fake_ros`): each used for a walk and reset answers
the next walk as a node launched again; the fault refuses once it has done what a reset
cannot undo; and the order the probe resets a launch's nodes in (consumers first)."""
import threading
import time
import types

import pytest
import rospy
from geometry_msgs.msg import PoseWithCovarianceStamped
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import JointState

import fake_ros
from fake_ros import bench_script
from epuck_vrep_compat.experiment.probe_walks import ChunkError, reset_node, reset_order
from epuck_vrep_compat.nodes.node_reset import ResetRefused

# rospy's own time setter, which the resets call, uses a deprecated threading name
pytestmark = pytest.mark.filterwarnings("ignore:notifyAll:DeprecationWarning")

def estimate(t, x=1.0):
    msg = PoseWithCovarianceStamped()
    msg.header.stamp = rospy.Time.from_sec(t)
    msg.pose.pose.position.x = x
    return msg


def relayed(fault, ros, shift):
    """What the fault relays of a walk: the ready message, then one estimate per step."""
    out = ros.publishers["/safety_bench/operator_pose"]
    start = len(out.sent)
    for k in range(0, 101):
        fault._on_step_estimate(estimate(0.05 * k, x=shift + 0.01 * k))
    return [(m.header.stamp.to_sec(), m.pose.pose.position.x) for m in out.sent[start:]]


@pytest.mark.parametrize("kind", ["none", "latency_0.3", "hidden_latency_0.3",
                                  "tracker_frozen"])
def test_a_fault_reset_relays_as_a_fault_launched_again(monkeypatch, kind):
    bench_fault = bench_script("bench_fault")
    params = {"fault": kind, "at_s": 2.0, "lockstep": True}
    ros = fake_ros.install(monkeypatch, params)
    expected = relayed(bench_fault.Fault(), ros, 0.0)
    ros = fake_ros.install(monkeypatch, params)
    used = bench_fault.Fault()
    assert relayed(used, ros, 5.0) != expected
    used.reset()
    assert ros.publishers["/safety_bench/operator_pose"].impl.latch is None
    assert relayed(used, ros, 0.0) == expected


@pytest.mark.parametrize("kind", ["camera_removed", "laser_lost", "monitor_killed"])
def test_a_fault_that_removed_or_killed_something_refuses_its_reset(monkeypatch, kind):
    bench_fault = bench_script("bench_fault")
    fake_ros.install(monkeypatch, {"fault": kind, "lockstep": True})
    fault = bench_fault.Fault()
    fault.reset()                               # not injected yet: nothing to undo
    fault.done = True
    with pytest.raises(ResetRefused, match=kind):
        fault.reset()


def truth_state(truth):
    return (truth.joints, truth.estimate, truth.kinematics, truth.last_clock, truth.step_s,
            truth.blob_seen, truth.estimates.take(), truth.estimates.frame_id)


def test_a_truth_reset_holds_what_a_truth_launched_again_holds(monkeypatch):
    bench_truth = bench_script("bench_truth")
    answer = types.SimpleNamespace(handle=7, result=1)
    fake_ros.install(monkeypatch, {"lockstep": True})
    monkeypatch.setattr(rospy, "ServiceProxy", lambda *_a, **_k: lambda *_x, **_y: answer)
    fresh = bench_truth.Truth()
    used = bench_truth.Truth()
    late = estimate(15.0)
    late.header.frame_id = "world"
    used._on_estimate(late)
    used._on_joints(JointState())
    used._on_blob(None, 0)
    used.kinematics, used.last_clock, used.step_s = object(), rospy.Time(15), 0.1
    used.reset()
    assert rospy.get_rostime() == rospy.Time(0)
    assert truth_state(used) == truth_state(fresh)


def monitor(monkeypatch, name, params=None):
    """The monitor script's main() run with stand-ins: (its Ros, its scale's publisher)."""
    ros = fake_ros.install(monkeypatch, params)
    monkeypatch.setattr(rospy, "init_node", lambda *_a, **_k: None)
    monkeypatch.setattr(rospy, "spin", lambda: None)
    bench_script(name).main()
    return ros, ros.publishers["/IRB140/speed_scale"]


def clocks(ros, times):
    for t in times:
        ros.subscribers["/clock"][0].deliver(Clock(clock=rospy.Time.from_sec(t)))


@pytest.mark.parametrize("name, ready", [("no_monitor", 1.0), ("distance_stop", 0.0)])
def test_a_monitor_reset_says_it_is_ready_again_and_answers_every_step_again(
        monkeypatch, name, ready):
    ros, scale = monitor(monkeypatch, name)
    assert [m.data for m in scale.sent] == [ready]              # ready at its start
    if name == "distance_stop":
        ros.subscribers["/operator_tracker/pose"][0].deliver(estimate(0.05, x=5.0))
    clocks(ros, [0.05, 0.05, 0.10])
    assert len(scale.sent) == 3                                  # one answer per new time
    answer = ros.services["~reset"](None)
    assert answer.success and [m.data for m in scale.sent[3:]] == [ready]
    clocks(ros, [0.05])                   # time from 0 again: a step, with no estimate
    assert len(scale.sent) == 5 and (name == "no_monitor" or scale.sent[-1].data == 0.0)


BENCH = ([("/operator_tracker/pose", ["/operator_tracker"]),
          ("/kinect/depth/image", ["/kinect"]),
          ("/safety_bench/operator_pose", ["/fault"]),
          ("/IRB140/speed_scale", ["/ssm_supervisor"]),
          ("/safety_bench/truth", ["/truth"]),
          ("/rosout", ["/fault", "/kinect", "/operator_tracker", "/ssm_supervisor", "/truth"])],
         [("/operator_tracker/pose", ["/fault", "/truth"]),
          ("/kinect/depth/image", ["/operator_tracker"]),
          ("/safety_bench/operator_pose", ["/ssm_supervisor"]),
          ("/IRB140/speed_scale", ["/vrep", "/experiment_probe"]),
          ("/clock", ["/fault", "/kinect", "/operator_tracker", "/ssm_supervisor", "/truth"]),
          ("/rosout", ["/rosout"])],
         [])


def test_a_launchs_nodes_are_reset_consumers_first():
    nodes = ["/fault", "/kinect", "/operator_tracker", "/ssm_supervisor", "/truth"]
    order = reset_order(nodes, BENCH)
    assert order == ["/ssm_supervisor", "/truth", "/fault", "/operator_tracker", "/kinect"]
    assert reset_order(["/a", "/b"], ([("/x", ["/a"]), ("/y", ["/b"])],
                                      [("/x", ["/b"]), ("/y", ["/a"])], [])) == ["/a", "/b"]
    assert reset_order([], BENCH) == []


def test_a_reset_that_hangs_fails_the_chunk_at_the_deadline_and_a_refusal_says_why(monkeypatch):
    release = threading.Event()

    def hung(*_a, **_k):
        release.wait(10.0)              # a node that never answers (released after the test)
        return types.SimpleNamespace(success=True, message="")
    monkeypatch.setattr(rospy, "ServiceProxy", lambda *_a, **_k: hung)
    with pytest.raises(ChunkError, match="did not answer in time"):
        reset_node("/stuck", deadline=time.monotonic() + 0.2)
    release.set()
    refused = types.SimpleNamespace(success=False, message="a camera was removed")
    monkeypatch.setattr(rospy, "ServiceProxy", lambda *_a, **_k: lambda *_x: refused)
    with pytest.raises(ChunkError, match="refused its reset: a camera was removed"):
        reset_node("/fault", deadline=time.monotonic() + 5.0)
    monkeypatch.setattr(rospy, "ServiceProxy", lambda *_a, **_k: lambda *_x: (
        _ for _ in ()).throw(rospy.ServiceException("gone")))
    with pytest.raises(ChunkError, match="failed: gone"):
        reset_node("/gone")
