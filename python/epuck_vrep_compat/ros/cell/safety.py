"""The cell's safety interface, for a speed-and-separation supervisor that is a plain client:

- ``/<robot>/speed_scale`` (``std_msgs/Float64``, in): the override of that robot's every
  motion (its script, joint commands from ``joint_command`` or ``/vrep``, its base), applied by
  the simulation at the next step; 1 = full speed, 0 = a protective stop that holds the joints.
  Values above 1 or below 0 are clamped; a non-finite value stops the robot (fail safe). Both
  with a throttled warning.
- ``/<robot>/safety_stop`` (``std_msgs/Bool``, latched, out on change): true while the
  simulator holds the robot because its speed scale went stale (the watchdog of
  ``cell/speed_watchdog.py``, on where a supervisor is configured: ``~speed_scale_timeout_s``,
  ``~speed_scale_robots``), with one warning when it falls and one line when it resumes.
- lock-step with the supervisor (``~lockstep``, :mod:`lockstep`): the simulator waits for the
  watched robots' scales after each step.
- ``/vrep/operator_separation`` (``epuck_vrep_compat/OperatorSeparation``): the closest points
  between the operator's body and every link, from the simulation's collision world (the C++
  core), for the operator where he is or stood where a tracker puts him.
"""
import math
import struct

import numpy as np
import rospy
from std_msgs.msg import Bool, Float64

from epuck_vrep_compat.cell.separation import NoOperator, separations
from epuck_vrep_compat.compat.cell_names import ros_robot_name
from epuck_vrep_compat.compat.topics import (
    OPERATOR_SEPARATION_SERVICE, SAFETY_STOP_TOPIC, SPEED_SCALE_TOPIC)
from epuck_vrep_compat.ros.cell.lockstep import ScaleLockstep
from epuck_vrep_compat.ros.messages import time_stamp
from epuck_vrep_compat.srv import OperatorSeparation, OperatorSeparationResponse


_COUNT = struct.Struct("<I")


class _SeparationResponse(OperatorSeparationResponse):
    """A successful answer written to the wire from the stacked :class:`Separations` (the
    same bytes as the message's own serialisation of its lists and points, without a
    ``geometry_msgs/Point`` per link and value: 31 links, 93 points, twice a step)."""

    def __init__(self, stamp, links):
        super().__init__(success=True, stamp=stamp, robot=links.robot, link=links.link,
                         distance=links.distance_m.tolist())
        self.arrays = links

    def serialize(self, buff):
        buff.write(b"\x01")                                 # success, an empty message
        buff.write(_COUNT.pack(0))
        buff.write(struct.pack("<2I", self.stamp.secs, self.stamp.nsecs))
        for names in (self.robot, self.link):
            buff.write(_COUNT.pack(len(names)))
            for name in names:
                encoded = name.encode("utf-8")
                buff.write(_COUNT.pack(len(encoded)))
                buff.write(encoded)
        links = self.arrays
        buff.write(_COUNT.pack(len(links.robot)))
        buff.write(np.ascontiguousarray(links.distance_m, dtype="<f8").tobytes())
        for points in (links.operator_point, links.link_point, links.link_point_local):
            buff.write(_COUNT.pack(len(points)))
            buff.write(np.ascontiguousarray(points, dtype="<f8").tobytes())


class CellSafety:
    """The speed-scale subscribers of the cell's robots and the separation service."""

    def __init__(self, sim, log, watchdog=(0.0, None), lockstep_timeout_s=0.0):
        """``watchdog``: (timeout_s, robots or None for all), given to the cell's watchdog;
        ValueError for a robot the cell does not have. ``lockstep_timeout_s`` > 0: the
        simulator waits for the same robots' scales after each step (:attr:`lockstep`)."""
        self.sim = sim
        self._log = log
        self.lockstep = None
        if lockstep_timeout_s > 0.0:
            robots = watchdog[1]
            self.lockstep = ScaleLockstep(
                lambda: [n for n in sim.cell.arm_by_name if robots is None or n in robots],
                lockstep_timeout_s, connected=self._scale_connected)
        self._scales = {}
        self._stops = {}                        # robot -> its safety_stop publisher
        self._stopped = {}                      # robot -> the flag last published
        sim.cell.commands.watch_speed_scale(*watchdog)
        self.sync()
        self._service = rospy.Service(OPERATOR_SEPARATION_SERVICE, OperatorSeparation,
                                      self._on_separation)

    def sync(self):
        """A removed robot's subscriber goes, an added robot's comes."""
        for name in [n for n in self._scales if n not in self.sim.cell.arm_by_name]:
            self._scales.pop(name).unregister()
            self._stops.pop(name).unregister()
            self._stopped.pop(name, None)
        for name in [n for n in self.sim.cell.arm_by_name if n not in self._scales]:
            self._scales[name] = rospy.Subscriber(
                SPEED_SCALE_TOPIC.format(robot=ros_robot_name(name)), Float64, self._on_scale,
                callback_args=name, queue_size=1)
            self._stops[name] = rospy.Publisher(
                SAFETY_STOP_TOPIC.format(robot=ros_robot_name(name)), Bool, queue_size=1,
                latch=True)

    def publish(self):
        """After a step: each robot's safety_stop when it changed (and the first time)."""
        watchdog = self.sim.cell.watchdog
        for name, publisher in self._stops.items():
            stopped = watchdog.stopped.get(name, False)
            if self._stopped.get(name) == stopped:
                continue
            if stopped:
                rospy.logwarn("%s: no %s for %.2f s of simulated time (the watchdog's timeout "
                              "is %.2f s): protective stop until a fresh scale arrives", name,
                              SPEED_SCALE_TOPIC.format(robot=ros_robot_name(name)),
                              watchdog.age_s(name, self.sim.time_s), watchdog.timeout_s)
            elif name in self._stopped and self._stopped[name]:
                rospy.loginfo("%s: a fresh speed scale arrived; the robot resumes", name)
            self._stopped[name] = stopped
            publisher.publish(Bool(stopped))

    def restart(self):
        """As built (a rewind; the node restarts the lock-step): each safety_stop sent again
        at the first step."""
        self._stopped.clear()

    def close(self):
        for subscriber in self._scales.values():
            subscriber.unregister()
        for publisher in self._stops.values():
            publisher.unregister()
        self._service.shutdown()

    def _scale_connected(self, name):
        sub = self._scales.get(name)
        return sub is not None and sub.get_num_connections() > 0

    def _on_scale(self, msg, name):
        value = msg.data
        if not math.isfinite(value):
            self._log.warn(f"{name}:speed_scale", "/%s/speed_scale: %s is not finite; the "
                           "robot stops (fail safe)", name, value)
        elif not 0.0 <= value <= 1.0:
            self._log.warn(f"{name}:speed_scale:range", "/%s/speed_scale: %s clamped to "
                           "[0, 1]", name, value)
        self.sim.cell.commands.speed_scale(name, value)
        if self.lockstep is not None:
            self.lockstep.answered(name)

    def _on_separation(self, req):
        with self.sim.lock:                     # a query of the collision world the step moves
            try:
                links = separations(self.sim.cell, req.ground_truth, req.x, req.y)
            except (NoOperator, ValueError) as error:
                self._log.warn("operator_separation", "%s: %s", OPERATOR_SEPARATION_SERVICE,
                               error)
                return OperatorSeparationResponse(success=False, message=str(error))
            stamp = time_stamp(self.sim.time_s)
        return _SeparationResponse(stamp, links)
