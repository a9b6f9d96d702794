"""``ssm_supervisor``: speed and separation monitoring (ISO/TS 15066) of the cell's robots, a
plain client of the simulator (the arithmetic is in :mod:`ssm_model`).

Every cycle (``~rate_hz``, simulation time): the operator's position (the tracker's estimate on
``~operator_topic``, ``geometry_msgs/PoseWithCovarianceStamped``, or with ``~ground_truth``
where he is) goes to ``/vrep/operator_separation``, which answers every link's minimum distance
to his body from the simulator's collision world; each link's speed at its closest point comes
from ``/<robot>/joint_states`` and ``/<robot>/robot_description``, plus the base's own motion
(a mobile base: the youBot's), from the root link's frame on TF between two cycles; the
robot's separation is its links' minimum, S_p is taken at its fastest link's speed, and the
speed scale goes to ``/<robot>/speed_scale``, which the simulator applies to whatever moves
the robot. The scale keeps S_p within the separation over its horizon: the estimate's age
(0 with ground truth) plus one cycle (the last period), :meth:`ArmGovernor.update`.

Published per robot under ``~<robot>/``: ``separation``, ``protective_separation``, ``scale``
and ``operator_uncertainty`` (Z_d) (``std_msgs/Float64``), ``protective_stop`` (``std_msgs/Bool``), ``status``
(``std_msgs/String``, latched: why the robot is stopped); ``~markers`` for rviz.

Fail safe: a missing, stale (older than ``~stale_s``) or non-finite operator estimate, stale
joint states or a failed separation query stop the robot (scale 0), with the reason on
``status`` and a throttled warning. With ``~lockstep`` (and the simulator's
``~lockstep_timeout_s``) it answers every step from that step's inputs (:mod:`ssm_pacing`),
and with ``~lockstep_operator`` (false) from that step's operator estimate too.
``~set_enabled`` (``std_srvs/SetBool``) turns the override off (scale 1, monitoring goes on)
and on again; ``~reset`` (``std_srvs/Trigger``, :mod:`node_reset`): as launched, for the next
run of one launch. Parameters: ``~robots`` (default: every robot the simulator reports),
``~ground_truth`` (false), ``~rate_hz`` (20), ``~stale_s`` (0.5) and the fields of
:class:`SsmParameters` with their defaults.
"""
import math

import numpy as np
import rospy
import tf2_ros
from geometry_msgs.msg import PoseWithCovarianceStamped
from std_srvs.srv import SetBool, SetBoolResponse
from visualization_msgs.msg import MarkerArray

from epuck_vrep_compat.compat.frames import WORLD_FRAME
from epuck_vrep_compat.compat.topics import OPERATOR_SEPARATION_SERVICE
from epuck_vrep_compat.nodes.ssm_channel import RobotChannel
from epuck_vrep_compat.nodes.ssm_markers import robot_markers
from epuck_vrep_compat.nodes.ssm_model import (
    SsmParameters, operator_uncertainty, protective_separation)
from epuck_vrep_compat.nodes.node_reset import ResetService, clear_tf, restart_ros_time
from epuck_vrep_compat.nodes.ssm_pacing import OperatorSteps, StepPacer
from epuck_vrep_compat.nodes.step_inputs import NotifyingTransformListener
from epuck_vrep_compat.ros.common.log import ThrottledLog
from epuck_vrep_compat.ros.common.params import ParamError, read_typed
from epuck_vrep_compat.srv import OperatorSeparation, OperatorSeparationRequest


def read_parameters():
    """(SsmParameters, robots, ground_truth, rate_hz, stale_s, operator_topic, lockstep);
    ParamError."""
    p = SsmParameters()
    for name, default in vars(SsmParameters()).items():
        setattr(p, name, read_typed(name, default, float))
    try:
        p.check()
    except ValueError as error:
        raise ParamError(str(error)) from None
    robots = rospy.get_param("~robots", [])
    if not isinstance(robots, list) or not all(isinstance(r, str) and r for r in robots):
        raise ParamError(f"parameter '~robots' must be a list of robot names, got {robots!r}")
    positive = (lambda v: v > 0), "must be > 0"
    lockstep = read_typed("lockstep", False, bool)
    if lockstep and not robots:
        raise ParamError("parameter '~lockstep': lock-step needs the robots named in '~robots'")
    return (p, robots, read_typed("ground_truth", False, bool),
            read_typed("rate_hz", 20.0, float, *positive),
            read_typed("stale_s", 0.5, float, *positive),
            read_typed("operator_topic", "/operator_tracker/pose", str), lockstep)


class SsmSupervisor:
    """The supervisor's state and its cycle (see the module's docstring)."""

    def __init__(self):
        (self.p, robots, self.ground_truth, self.rate_hz, self.stale_s,
         operator_topic, self.lockstep) = read_parameters()
        rate_hz = self.rate_hz
        self.start_state()
        self.tf_buffer = tf2_ros.Buffer(rospy.Duration(5.0))
        self._tf_listener = NotifyingTransformListener(self.tf_buffer)
        self.operator_steps = (OperatorSteps() if self.lockstep and not self.ground_truth
                               and read_typed("lockstep_operator", False, bool) else None)
        self.pacer = pacer = (StepPacer({}, self.cycle, self._tf_listener, self.operator_steps)
                              if self.lockstep else None)
        self.channels = {name: RobotChannel(name, self.p, self.lockstep,
                                            pacer.on_joints if pacer else None)
                         for name in robots}
        self.fixed_robots = bool(robots)
        self.query = self._connect()
        self.markers = rospy.Publisher("~markers", MarkerArray, queue_size=1)
        if not self.ground_truth:
            steps = self.operator_steps
            self._sub = rospy.Subscriber(operator_topic, PoseWithCovarianceStamped,
                                         steps.on_message if steps else self._on_operator,
                                         queue_size=100 if steps else 1)
        rospy.Service("~set_enabled", SetBool, self._on_set_enabled)
        rospy.loginfo("ssm_supervisor: %s, %s Hz, operator %s; T_r %.2f s, T_s %.2f s, "
                      "C %.2f m, Z_r %.2f m, v_h %.2f m/s", robots or "every robot", rate_hz,
                      "ground truth" if self.ground_truth else operator_topic,
                      self.p.reaction_time_s, self.p.stopping_time_s, self.p.intrusion_m,
                      self.p.robot_uncertainty_m, self.p.human_speed_m_s)
        if pacer is not None:             # one cycle per step, on that step's joint states
            rospy.loginfo("ssm_supervisor: in lock-step with the simulator")
            pacer.channels = self.channels
            pacer.handshake()
        else:
            self.timer = rospy.Timer(rospy.Duration(1.0 / rate_hz), self.cycle)

    def start_state(self):
        """What a run changes, as at the start (the robots' channels apart)."""
        self.enabled = True
        self.log = ThrottledLog()
        self.operator = None
        self.cycle_s = 1.0 / self.rate_hz      # the period, until two cycles tell it
        self._last_cycle = rospy.Time(0)

    def reset(self):
        """``~reset``: as launched (the simulator rewound, paused before its first step): each
        robot's channel too, the override on; in lock-step the ready scale again once the
        operator's estimate is ready (:meth:`StepPacer.restart`), else the timer from 0."""
        restart_ros_time()
        clear_tf(self._tf_listener)
        self.start_state()
        for channel in self.channels.values():
            channel.restart()
        if self.pacer is not None:
            self.pacer.restart()
        else:
            self.timer.shutdown()
            self.timer = rospy.Timer(rospy.Duration(1.0 / self.rate_hz), self.cycle)

    def _on_operator(self, msg):
        self.operator = msg

    def _on_set_enabled(self, req):
        self.enabled = bool(req.data)
        rospy.loginfo("ssm_supervisor: override %s", "on" if self.enabled else "off")
        return SetBoolResponse(success=True, message="")

    def operator_input(self, now):
        """(request, Z_d, the position's age [s], None) or (None, None, None, why the
        operator's position is unusable)."""
        if self.ground_truth:
            return (OperatorSeparationRequest(ground_truth=True), operator_uncertainty(self.p),
                    0.0, None)
        msg = self.operator
        if msg is None:
            return None, None, None, "no operator estimate yet"
        age = (now - msg.header.stamp).to_sec()
        if age > self.stale_s:
            return None, None, None, f"operator estimate stale ({age:.2f} s old)"
        position, cov = msg.pose.pose.position, msg.pose.covariance
        xy_cov = np.array([[cov[0], cov[1]], [cov[6], cov[7]]])
        if not (math.isfinite(position.x) and math.isfinite(position.y)
                and np.isfinite(xy_cov).all()):
            return None, None, None, "operator estimate not finite"
        return (OperatorSeparationRequest(ground_truth=False, x=position.x, y=position.y),
                operator_uncertainty(self.p, xy_cov), max(age, 0.0), None)

    @staticmethod
    def _connect():
        """One connection kept for every query (a new one per call cost the simulator, the
        master and this node about 1.5 ms a step)."""
        return rospy.ServiceProxy(OPERATOR_SEPARATION_SERVICE, OperatorSeparation,
                                  persistent=True)

    def separation(self, request):
        """The simulator's answer, or (None, why); a broken connection (the simulator started
        again) is opened anew and the query asked once more before it counts as failed."""
        for retry in (False, True):
            try:
                answer = self.query(request)
                break
            except (rospy.ServiceException, rospy.ROSException, OSError) as error:
                self.query.close()
                self.query = self._connect()
                if retry:
                    return None, f"separation query failed: {error}"
        return (answer, None) if answer.success else (None, answer.message)

    def cycle(self, _event=None, now=None):
        """One cycle at ``now`` (lock-step: the step's stamp; None: the clock's time now);
        never twice at one simulated time (a timer catching up after a jump of the clock
        fires twice)."""
        now = now if now is not None else rospy.Time.now()
        if now <= self._last_cycle:
            return
        if self._last_cycle > rospy.Time(0):
            self.cycle_s = min((now - self._last_cycle).to_sec(), self.stale_s)
        self._last_cycle = now
        if self.operator_steps is not None:
            self.operator = self.operator_steps.next() or self.operator
            if rospy.is_shutdown():          # ended while waiting (killed): say nothing more
                return
        request, z_d, age, fault = self.operator_input(now)
        horizon = None if fault is not None else age + self.cycle_s
        answer = None
        if fault is None:
            answer, fault = self.separation(request)
        if answer is not None and not self.fixed_robots:
            for name in sorted(set(answer.robot) - set(self.channels)):
                self.channels[name] = RobotChannel(name, self.p)
        markers = MarkerArray()
        for index, channel in enumerate(self.channels.values()):
            try:
                markers.markers += self.supervise(channel, index, now, answer, z_d, fault,
                                                  horizon)
            except Exception as error:      # noqa: BLE001  a timer thread must not die: stop
                self._fail(channel, f"supervisor error: {error!r}")
        self.markers.publish(markers)

    def supervise(self, channel, index, now, answer, z_d, fault, horizon=0.0):
        """One robot's cycle; returns its markers (``horizon``: :meth:`ArmGovernor.update`'s)."""
        rows = [] if answer is None else [i for i, r in enumerate(answer.robot)
                                          if r == channel.name]
        joints = channel.joints
        if fault is None and (joints is None
                              or (now - joints.header.stamp).to_sec() > self.stale_s):
            fault = "joint states missing or stale"
        if fault is None and not rows:
            fault = "the simulator reports no links of this robot"
        speeds = None
        if fault is None:
            speeds = channel.link_speeds([answer.link[i] for i in rows],
                                         [_xyz(answer.link_point_local[i]) for i in rows],
                                         self.tf_buffer, now if self.lockstep else None)
            if speeds is None or not np.isfinite(speeds).all():
                fault = "link speeds unknown (robot_description, joint states or TF)"
        if fault is not None:
            return self._fail(channel, fault)
        distances = np.array([answer.distance[i] for i in rows])
        nearest = rows[int(np.argmin(distances))]
        fastest = float(speeds.max())
        channel.governor.learn_speed(fastest, now.to_sec())
        separation = float(distances.min())
        scale = channel.governor.update(separation, z_d, horizon)
        s_p = protective_separation(self.p, z_d, fastest)
        status = "ok" if scale > 0.0 else f"protective stop: separation {separation:.2f} m"
        channel.report(separation, s_p, scale if self.enabled else 1.0, status, z_d)
        return robot_markers(WORLD_FRAME, now, channel.name, index,
                             _xyz(answer.operator_point[nearest]),
                             _xyz(answer.link_point[nearest]), s_p, scale)

    def _fail(self, channel, why):
        """Fail safe: the robot stops (unless the override is off), and says why."""
        channel.governor.stop()
        kind = why.split(" (")[0]             # throttled per kind of fault, not per number
        self.log.warn(f"{channel.name}:{kind}", "ssm_supervisor: %s stopped: %s",
                      channel.name, why)
        channel.report(math.nan, math.nan, 0.0 if self.enabled else 1.0, "stopped: " + why)
        return []


def _xyz(point):
    return np.array([point.x, point.y, point.z])


def main():
    rospy.init_node("ssm_supervisor")
    try:
        ResetService(SsmSupervisor().reset)
    except ParamError as error:
        rospy.logfatal("ssm_supervisor: %s", error)
        return 2
    rospy.spin()
    return 0
