"""ScaleLockstep's pure logic: answers matched to the steps they answer, a lost robot waited
for again only once it has caught up, surplus scales ignored, a stop ending a wait."""
import threading
import time

from epuck_vrep_compat.ros.cell.lockstep import ScaleLockstep

ROBOTS = ["irb140", "ur5"]


def lockstep(timeout_s=0.05):
    return ScaleLockstep(lambda: ROBOTS, timeout_s)


def answer_all(ls, times=1):
    for _ in range(times):
        for robot in ROBOTS:
            ls.answered(robot)


def test_waits_for_the_first_scale_then_for_each_step():
    ls = lockstep()
    assert ls.missing() == [("irb140", 0), ("ur5", 0)]
    answer_all(ls)                                  # the handshake
    assert ls.missing() == []
    ls.stepped()
    assert ls.missing() == [("irb140", 1), ("ur5", 1)]
    ls.answered("irb140")
    assert ls.missing() == [("ur5", 1)]
    ls.answered("ur5")
    assert ls.missing() == []
    assert ls.late_steps == 0


def test_a_late_answer_counts_for_the_step_it_answers_not_the_next():
    ls = lockstep()
    answer_all(ls)
    ls.stepped()                                    # step 1
    ls.answered("irb140")
    ls.wait()                                       # ur5 times out: lost
    assert ls.missing() == []
    ls.stepped()                                    # step 2, taken without ur5's answer
    assert ls.late_steps == 1
    assert ls.missing() == [("irb140", 2)]
    ls.answered("irb140")
    ls.answered("ur5")                              # ur5's late answer to step 1
    assert ls.missing() == []                       # still not waited for: one step behind
    ls.stepped()                                    # step 3
    assert ls.late_steps == 2
    ls.answered("irb140")
    ls.answered("ur5")                              # ur5 answers step 2: still behind
    assert ls.missing() == []
    ls.answered("ur5")                              # ...and step 3: caught up, waited for again
    ls.stepped()                                    # step 4
    assert ls.late_steps == 2
    assert ls.missing() == [("irb140", 4), ("ur5", 4)]


def test_a_surplus_scale_does_not_release_a_step_early():
    ls = lockstep()
    answer_all(ls)
    ls.stepped()
    answer_all(ls)
    answer_all(ls)                                  # a latched scale delivered again
    ls.stepped()
    assert ls.missing() == [("irb140", 2), ("ur5", 2)]


def test_a_robot_without_a_first_scale_joins_at_its_first():
    ls = lockstep()
    ls.answered("irb140")
    ls.wait()                                       # ur5 lost before the first step
    ls.stepped()
    assert ls.late_steps == 1
    ls.answered("irb140")
    ls.answered("ur5")                              # its handshake, after step 1
    ls.stepped()                                    # from here ur5 answers each step
    assert ls.missing() == [("irb140", 2)]
    ls.answered("irb140")
    ls.answered("ur5")
    ls.stepped()
    assert ls.missing() == [("irb140", 3), ("ur5", 2)]


def test_a_stop_request_ends_the_wait():
    ls = ScaleLockstep(lambda: ROBOTS, 3600.0)
    stop = threading.Event()
    ls.stop_requested = stop.is_set
    waiter = threading.Thread(target=ls.wait)
    waiter.start()
    time.sleep(0.1)
    assert waiter.is_alive()
    stop.set()
    waiter.join(10.0)
    assert not waiter.is_alive()
    assert ls.missing() == [("irb140", 0), ("ur5", 0)]   # not lost: stopped, not timed out
