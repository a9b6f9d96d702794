#!/usr/bin/python3
"""Records one lock-step safety run for test_safety_lockstep.py: V-REP's synchronous mode, one
trigger per step (or, with ~by_step_service, the paused simulation advanced by one step per
call of /vrep/step), and after each step the operator's true separation from the simulator
(/vrep/operator_separation, stamped with the step's simulated time); every speed scale the
supervisor sends, in order. Writes ~out (CSV: stamp_ns, the robot's minimum separation, its
nearest link) and ~out.scales, then exits (the run's launch marks it required)."""
import threading
import time

import rospy
from rosgraph_msgs.msg import Clock
from std_msgs.msg import Float64
from std_srvs.srv import Empty
from vrep_common.srv import simRosSynchronous, simRosSynchronousTrigger

from epuck_vrep_compat.srv import OperatorSeparation, StepSimulation


def main():
    rospy.init_node("lockstep_recorder")
    duration_s, out = rospy.get_param("~duration_s"), rospy.get_param("~out")
    robot = rospy.get_param("~robot", "IRB140")
    cond, clock, scales = threading.Condition(), [rospy.Time(0)], []

    def on_clock(msg):
        with cond:
            clock[0] = msg.clock
            cond.notify_all()
    rospy.Subscriber("/clock", Clock, on_clock, queue_size=100)
    rospy.Subscriber(f"/{robot}/speed_scale", Float64, lambda m: scales.append(m.data),
                     queue_size=10000)
    by_step_service = rospy.get_param("~by_step_service", False)
    for name in ("/vrep/simRosSynchronous", "/vrep/simRosSynchronousTrigger", "/vrep/unpause",
                 "/vrep/step", "/vrep/operator_separation"):
        rospy.wait_for_service(name, timeout=120)
    separation = rospy.ServiceProxy("/vrep/operator_separation", OperatorSeparation,
                                    persistent=True)
    if by_step_service:                  # the simulation stays paused
        step = rospy.ServiceProxy("/vrep/step", StepSimulation, persistent=True)
    else:
        trigger = rospy.ServiceProxy("/vrep/simRosSynchronousTrigger", simRosSynchronousTrigger,
                                     persistent=True)
        rospy.ServiceProxy("/vrep/simRosSynchronous", simRosSynchronous)(enable=1)
        rospy.ServiceProxy("/vrep/unpause", Empty)()
    rows = []
    while not rospy.is_shutdown():
        if by_step_service:
            answer = step(steps=1)
            if not answer.success:
                raise RuntimeError(f"/vrep/step failed: {answer.message}")
        else:
            with cond:
                before = clock[0]
            trigger()
            deadline = time.monotonic() + 60.0
            with cond:
                while clock[0] <= before and time.monotonic() < deadline:
                    cond.wait(0.5)
        answer = separation(ground_truth=True)
        mine = [(d, link) for r, link, d in zip(answer.robot, answer.link, answer.distance)
                if r == robot]
        distance, link = min(mine)
        rows.append((answer.stamp.to_nsec(), repr(distance), link))
        if answer.stamp.to_sec() >= duration_s:
            break
    time.sleep(0.5)                      # the last step's answers arrive
    with open(out, "w") as f:
        f.write("stamp_ns,separation_m,link\n")
        f.writelines(f"{t},{d},{link}\n" for t, d, link in rows)
    with open(out + ".scales", "w") as f:
        f.writelines(f"{s!r}\n" for s in scales)


if __name__ == "__main__":
    main()
