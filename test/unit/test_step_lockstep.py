"""StepLockstep without a handshake (the e-puck face's cmd_vel lock-step) and Locksteps (every
face's at once): no wait before the first step, what came before it answers no step, one
answer per robot per step after it, an early answer counted for the next step, a lost robot
waited for again once it has caught up."""
import threading
import time

from epuck_vrep_compat.ros.common import late_steps
from epuck_vrep_compat.ros.common.lockstep import Locksteps, StepLockstep

ROBOTS = ["ePuck0", "ePuck1"]


def lockstep(robots=ROBOTS, timeout_s=0.05):
    return StepLockstep(lambda: robots, timeout_s, "cmd_vel", handshake=False,
                        early_answers=True)


def test_no_wait_before_the_first_step_then_one_answer_per_step():
    ls = lockstep()
    assert ls.missing() == []                       # a controller answers step 1's sensors
    ls.wait()                                       # returns at once, nobody lost
    ls.stepped()                                    # step 1
    assert ls.missing() == [("ePuck0", 0), ("ePuck1", 0)]
    ls.answered("ePuck0")
    assert ls.missing() == [("ePuck1", 0)]
    ls.answered("ePuck1")
    assert ls.missing() == []
    ls.stepped()                                    # step 2
    assert ls.missing() == [("ePuck0", 1), ("ePuck1", 1)]
    assert ls.late_steps == 0


def test_a_command_before_the_first_step_answers_no_step():
    ls = lockstep()
    ls.answered("ePuck0")                           # a stop command at the node's start
    ls.stepped()                                    # step 1: one more than the baseline
    assert ls.missing() == [("ePuck0", 1), ("ePuck1", 0)]
    ls.answered("ePuck0")
    ls.answered("ePuck1")
    assert ls.missing() == []


def test_a_late_command_counts_for_the_step_it_answers():
    ls = lockstep()
    ls.stepped()                                    # step 1
    ls.answered("ePuck0")
    ls.wait()                                       # ePuck1 times out: lost
    ls.stepped()                                    # step 2, without ePuck1's answer
    assert ls.late_steps == 1
    assert ls.missing() == [("ePuck0", 1)]
    ls.answered("ePuck0")
    ls.answered("ePuck1")                           # its late answer to step 1: behind
    ls.stepped()                                    # step 3
    assert ls.late_steps == 2
    ls.answered("ePuck1")
    ls.answered("ePuck1")                           # steps 2 and 3: caught up
    assert ls.missing() == [("ePuck0", 2)]
    ls.answered("ePuck0")
    ls.stepped()                                    # step 4: both waited for
    assert ls.late_steps == 2
    assert ls.missing() == [("ePuck0", 3), ("ePuck1", 3)]


def test_a_command_beyond_the_steps_answers_the_next_one():
    ls = lockstep(robots=["ePuck0"])
    ls.stepped()                                    # step 1
    ls.answered("ePuck0")
    ls.answered("ePuck0")                           # a timer that fired twice in step 1
    ls.stepped()                                    # step 2: already answered
    assert ls.missing() == []
    ls.stepped()                                    # step 3
    assert ls.missing() == [("ePuck0", 2)]


def test_a_lost_robot_that_catches_up_early_is_waited_for_again():
    ls = lockstep(robots=["ePuck0"])
    ls.stepped()
    ls.wait()                                       # lost at step 1
    ls.stepped()                                    # step 2, late
    ls.answered("ePuck0")
    ls.answered("ePuck0")
    ls.answered("ePuck0")                           # steps 1, 2 and (early) 3
    ls.stepped()                                    # step 3: waited for again, answered
    assert ls.late_steps == 1
    assert ls.missing() == []
    ls.stepped()
    assert ls.missing() == [("ePuck0", 3)]


def test_only_the_watched_robots_are_waited_for():
    ls = lockstep(robots=["ePuck1"])
    ls.answered("ePuck0")                           # not watched: counted, never waited for
    ls.stepped()
    assert ls.missing() == [("ePuck1", 0)]


def test_locksteps_waits_for_every_face_and_is_none_without_one():
    assert Locksteps.of([None, None]) is None
    cmd = lockstep(robots=["ePuck0"], timeout_s=3600.0)
    scale = StepLockstep(lambda: ["irb140"], 3600.0, "speed scale")
    both = Locksteps.of([scale, None, cmd])
    stop = threading.Event()
    both.stop_requested = stop.is_set
    assert cmd.stop_requested == stop.is_set and scale.stop_requested == stop.is_set
    scale.answered("irb140")                        # the supervisor's handshake
    both.wait()
    both.stepped()
    assert scale.missing() == [("irb140", 1)] and cmd.missing() == [("ePuck0", 0)]
    waiter = threading.Thread(target=both.wait)
    waiter.start()
    scale.answered("irb140")
    cmd.answered("ePuck0")
    waiter.join(60.0)
    assert not waiter.is_alive()
    assert scale.missing() == [] and cmd.missing() == []


def test_settle_waits_for_the_last_steps_answer_still_on_its_way():
    ls = StepLockstep(lambda: ROBOTS, 5.0, "speed scale", handshake=True)
    ls.settle()                                     # nothing published: nothing owed
    for robot in ROBOTS:
        ls.answered(robot)                          # the handshake
    ls.stepped()
    ls.answered("ePuck0")
    late = threading.Timer(0.05, ls.answered, ("ePuck1",))
    late.start()
    ls.settle()                                     # returns once ePuck1's answer is in
    assert ls.missing() == []
    late.join()
    ls.restart()                                    # so it answers no step of the next run
    assert ls.missing() == [("ePuck0", 0), ("ePuck1", 0)]


def test_settle_gives_up_after_the_time_out_and_marks_nobody_lost():
    ls = lockstep(timeout_s=0.01)
    ls.stepped()
    ls.answered("ePuck0")
    ls.settle()                                     # ePuck1 never answers
    assert ls.missing() == [("ePuck1", 0)] and ls.late_steps == 0
    both = Locksteps([ls, lockstep(timeout_s=0.01)])
    both.settle()


def test_a_step_without_a_connected_robots_answer_is_a_late_step_for_the_experiment():
    connected = {"ePuck0": True, "ePuck1": False}
    ls = StepLockstep(lambda: ROBOTS, 0.05, "cmd_vel", handshake=False, early_answers=True,
                      connected=lambda r: connected[r])
    ls.stepped()
    ls.answered("ePuck0")
    ls.wait()                                       # ePuck1, gone, times out: lost
    ls.stepped()
    assert (ls.late_steps, ls.late.count) == (1, 0)     # a dead client: nothing it changed
    ls.answered("ePuck0")
    ls.wait()
    connected["ePuck1"] = True                      # there after all: a hung client
    ls.stepped()
    assert (ls.late_steps, ls.late.count) == (2, 1)


def test_every_nodes_late_steps_add_up():
    assert late_steps.total({"vrep": 3, "operator_tracker": 1, "ns": {"truth": 2}}) == 6
    assert late_steps.total({}) == 0 and late_steps.total("junk") == 0


def test_a_client_that_answered_and_disconnected_is_not_waited_for():
    """A SIGKILLed supervisor: its connection closes after its last answer; the next step is
    not held for the hour a hung one would be, and it is waited for again once it catches up."""
    connected = {"irb140": True}
    ls = StepLockstep(lambda: ["irb140"], 3600.0, "speed scale",
                      connected=lambda r: connected[r])
    ls.answered("irb140")                           # the handshake
    ls.wait()
    ls.stepped()
    ls.answered("irb140")
    ls.wait()
    ls.stepped()
    connected["irb140"] = False
    waiter = threading.Thread(target=ls.wait)
    waiter.start()
    waiter.join(60.0)
    assert not waiter.is_alive()
    assert ls.missing() == []                       # lost: not waited for
    ls.stepped()
    assert (ls.late_steps, ls.late.count) == (1, 0)     # a dead client: not the machine's
    connected["irb140"] = True
    for _ in range(2):
        ls.answered("irb140")                       # a new client answers both steps since
    ls.stepped()
    assert ls.missing() == [("irb140", 4)]           # waited for again: step 4 is owed


def test_a_client_never_heard_is_waited_for_though_not_connected_yet():
    ls = StepLockstep(lambda: ["irb140"], 0.2, "speed scale", connected=lambda r: False)
    started = time.monotonic()
    ls.wait()                                       # the handshake: a supervisor starting
    assert time.monotonic() - started >= 0.2
