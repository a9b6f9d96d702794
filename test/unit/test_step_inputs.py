"""Lock-step's per-step inputs of the client nodes (no master): which steps a sensor of a
period delivers at, a stamped topic's inbox and its wait, and the supervisor's count of the
operator's estimates (the n-th after the ready message is step n's)."""
import threading
import time

import rospy
from geometry_msgs.msg import PoseWithCovarianceStamped

from epuck_vrep_compat.nodes import ssm_pacing
from epuck_vrep_compat.nodes.ssm_pacing import OperatorSteps
from epuck_vrep_compat.nodes.step_inputs import Inbox, due

STEP_S = 0.05


def estimate(t):
    msg = PoseWithCovarianceStamped()
    msg.header.stamp = rospy.Time.from_sec(t)
    msg.pose.pose.position.x = t
    return msg


def later(seconds, call, *args):
    threading.Timer(seconds, call, args).start()


def test_a_period_of_two_steps_falls_on_every_second_step_and_none_on_zero():
    stamps = [rospy.Time.from_sec(k * STEP_S).to_sec() for k in range(0, 41)]
    steps = [t for prev, t in zip(stamps, stamps[1:]) if due(prev, t, 0.1)]
    assert len(steps) == 20 and all(abs(t / 0.1 - round(t / 0.1)) < 1e-9 for t in steps)
    assert not any(due(prev, t, 0.0) for prev, t in zip(stamps, stamps[1:]))
    # a period that is no multiple of the step: once per period, at the first step after it
    assert sum(due(prev, t, 0.12) for prev, t in zip(stamps, stamps[1:])) == 16


def test_the_inbox_waits_for_the_steps_stamp_and_gives_each_message_once():
    box = Inbox()
    assert box.frame_id == ""
    first = estimate(0.05)
    first.header.frame_id = "Hokuyo"
    box.put(first)
    assert box.wait_for(rospy.Time.from_sec(0.05), timeout_s=0.0) and box.frame_id == "Hokuyo"
    later(0.05, box.put, estimate(0.10))
    assert box.wait_for(rospy.Time.from_sec(0.10), timeout_s=30.0)
    assert box.take().header.stamp.to_sec() == 0.10 and box.take() is None


def test_the_inbox_forgets_a_message_older_than_the_step_and_keeps_the_steps_own():
    box = Inbox()
    box.put(estimate(0.0))                   # sent before the start: heard or not, by chance
    box.discard_before(rospy.Time.from_sec(0.05))
    assert box.take() is None
    box.put(estimate(0.10))
    box.discard_before(rospy.Time.from_sec(0.10))
    assert box.take().header.stamp.to_sec() == 0.10


def test_the_inbox_gives_up_when_the_publisher_has_gone_or_the_time_is_out():
    box = Inbox()
    start = time.monotonic()
    assert not box.wait_for(rospy.Time.from_sec(0.1), timeout_s=30.0, gone=lambda: True)
    assert time.monotonic() - start < 30.0
    assert not box.wait_for(rospy.Time.from_sec(0.1), timeout_s=0.01)


def test_the_n_th_estimate_after_the_ready_one_is_step_ns_however_late():
    steps = OperatorSteps()
    steps.on_message(estimate(0.3))          # before the ready message: no step's
    later(0.05, steps.on_message, estimate(0.0))
    steps.wait_ready()
    steps.on_message(estimate(0.0))          # the latched ready message again: nothing
    for t in (0.05, 0.10):
        steps.on_message(estimate(t))
    assert steps.next().header.stamp.to_sec() == 0.05
    assert steps.next().header.stamp.to_sec() == 0.10
    later(0.05, steps.on_message, estimate(0.02))     # an old stamp (a held-back estimate)
    assert steps.next().header.stamp.to_sec() == 0.02


def test_a_missing_estimate_costs_its_step_only(monkeypatch):
    steps = OperatorSteps()
    steps.on_message(estimate(0.0))
    steps.on_message(estimate(0.05))
    assert steps.next().header.stamp.to_sec() == 0.05
    monkeypatch.setattr(ssm_pacing, "INPUT_TIMEOUT_S", 0.01)
    assert steps.next() is None                       # step 2's has not come
    steps.on_message(estimate(0.10))                  # step 2's, late
    steps.on_message(estimate(0.15))
    assert steps.next().header.stamp.to_sec() == 0.15
