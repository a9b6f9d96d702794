"""The operator tracker in lock-step (``~lockstep``): one estimate per simulation step, made
once, from that step's inputs alone, whatever order they arrive in.

At each new ``/clock`` time t (:class:`step_inputs.StepClock`), the step's inputs:

- the laser's scan, when the laser scans at t (every ``~laser_period_s``, 0.1 s: the cell's
  laser scans on multiples of its period, :func:`step_inputs.due`, and at time 0, at a launch
  or a rewind, a scan it sends with the first step), waited for by its stamp (had the first
  step not waited for the scan of time 0, whether it came before that step's estimate would
  have changed the laser's background, and so a walk's row, by chance);
- the Kinect's depth image, when the Kinect node in lock-step takes one at t (every
  ``~kinect_period_s``, 0.1 s: its rate; 0 without it), waited for by its stamp;
- the ceiling cameras' blobs, read from ``/vrep`` (``simRosGetFloatSignal``): their topics
  carry no stamp and say nothing while he is out of view, so a missing message could not be
  told from a late one. The simulator waits for the monitor's answer to this step, and the
  monitor for this estimate, so ``/vrep`` answers from the step's state.

An input whose sensor ``/vrep`` no longer has (the laser removed at an earlier step; asked by
the name its messages carry as their frame, only when the step's message has not come yet) or
whose publisher has gone is not waited for; one that does not come within
:data:`step_inputs.INPUT_TIMEOUT_S` of wall time is given up, with a warning, and counted in
the experiment's late steps (``ros/common/late_steps.py``). The
estimate, stamped t, goes out for every step, a position of NaN while there is no track: a
reader in lock-step (the supervisor's ``~lockstep_operator``) takes the n-th message as the n-th
step's. Before the first step, once its inputs are connected, the tracker sends a latched
message stamped 0 (NaN): the readers' sign that it is ready.
"""
import time

import rospy
from vrep_common.srv import simRosGetFloatSignal, simRosGetObjectHandle

from epuck_vrep_compat.compat.topics import BLOB_TOPIC_FORMAT, NODE_NAMESPACE
from epuck_vrep_compat.nodes.step_inputs import StepClock, due
from epuck_vrep_compat.ros.common.late_steps import LateSteps

SIGNAL_SERVICE = NODE_NAMESPACE + "simRosGetFloatSignal"
HANDLE_SERVICE = NODE_NAMESPACE + "simRosGetObjectHandle"


class TrackerSteps:
    """Drives an :class:`operator_tracker.OperatorTracker` once per step (see the module)."""

    def __init__(self, tracker, laser_period_s, kinect_period_s):
        self.tracker = tracker
        # (what, inbox, subscriber, period, whether the sensor also sends one at the first step)
        self.inputs = [("laser scan", tracker.scan, tracker.scan_sub, laser_period_s, True),
                       ("depth image", tracker.depth, tracker.depth_sub, kinect_period_s, False)]
        self.signals = {key: BLOB_TOPIC_FORMAT.format(camera=key[0], axis=key[1]).rsplit("/", 1)[1]
                        for key in tracker.blobs}
        rospy.wait_for_service(SIGNAL_SERVICE)
        self.get_signal = rospy.ServiceProxy(SIGNAL_SERVICE, simRosGetFloatSignal,
                                             persistent=True)
        self.get_handle = rospy.ServiceProxy(HANDLE_SERVICE, simRosGetObjectHandle,
                                             persistent=True)
        self.gone = set()                   # sensors /vrep no longer has
        self.late = LateSteps()             # inputs given up: for the experiment's row
        self.clock = StepClock(self.step)
        self.handshake()

    def restart(self):
        """As built (the tracker reset): every sensor there again, ``/clock`` from 0, and the
        ready message again."""
        self.gone = set()
        self.clock.reset()
        self.handshake()

    def handshake(self):
        """Once ``/clock`` and every input waited for are connected: the latched message
        stamped 0."""
        subscribers = [self.clock.subscriber] + [sub for _, _, sub, period, _ in self.inputs
                                                 if period > 0.0]
        while not rospy.is_shutdown() and any(s.get_num_connections() == 0
                                              for s in subscribers):
            time.sleep(0.02)
        self.tracker.publish(rospy.Time(0))

    def step(self, stamp, previous):
        """The estimate of the step at ``stamp`` (the previous step's at ``previous``)."""
        t, t_prev = stamp.to_sec(), previous.to_sec()
        for what, inbox, sub, period, at_start in self.inputs:
            inbox.discard_before(stamp)
            due_now = due(t_prev, t, period) or (at_start and period > 0.0 and t_prev == 0.0)
            if (not due_now or inbox.wait_for(stamp, timeout_s=0.0)
                    or not self.sensor_exists(inbox.frame_id)):
                continue
            if (not inbox.wait_for(stamp, gone=lambda s=sub: s.get_num_connections() == 0)
                    and sub.get_num_connections() > 0):
                self.tracker.log.warn(f"late:{what}", "operator_tracker: no %s of the step at "
                                      "%.3f s; estimating without it", what, t)
                self.late.add()
        self.read_blobs(t)
        if not self.tracker.cycle(now=stamp):
            self.tracker.publish(stamp)

    def sensor_exists(self, name):
        """False when ``/vrep`` has no object ``name`` (True for no name yet, or no answer);
        a sensor found gone is not asked for again (nor waited for)."""
        if not name or name in self.gone:
            return not name
        try:
            exists = self.get_handle(name).handle >= 0
        except (rospy.ServiceException, rospy.ROSException):
            return True
        if not exists:
            self.gone.add(name)
            rospy.loginfo("operator_tracker: %s is gone; not waited for any more", name)
        return exists

    def read_blobs(self, t):
        """Each blob signal set now, as if its message had come at ``t`` (one cleared keeps its
        last value and time, as a topic gone silent does: ``~fresh_s`` then ages it out)."""
        for key, name in self.signals.items():
            try:
                answer = self.get_signal(name)
            except (rospy.ServiceException, rospy.ROSException) as error:
                self.tracker.log.warn("blob", "operator_tracker: %s not read: %s", name, error)
                continue
            if answer.result == 1:
                self.tracker.blobs[key] = (t, float(answer.signalValue))
