"""Each cell robot's joint topics: ``/<robot>/joint_states`` out every step;
``/<robot>/joint_command`` and, for a mobile base, ``/<robot>/cmd_vel`` in.

``joint_command`` (``sensor_msgs/JointState``): positions are target positions, or, with no
positions, velocities are target velocities; names select joints, none = all in order. A command
stops the robot's default script until the simulation is stopped or reset. Commands arrive on
rospy's threads and go to the model through the cell's command interface
(:class:`~epuck_vrep_compat.cell.commands.CellCommands`), which takes the simulation lock.
"""
import rospy
from geometry_msgs.msg import Twist
from sensor_msgs.msg import JointState

from epuck_vrep_compat.cell.commands import CLAMPED, UNKNOWN
from epuck_vrep_compat.compat.cell_names import ros_robot_name
from epuck_vrep_compat.compat.topics import (
    BASE_CMD_VEL_TOPIC, JOINT_COMMAND_TOPIC, JOINT_STATES_TOPIC)
from epuck_vrep_compat.cell.devices.articulated import POSITION, VELOCITY
from epuck_vrep_compat.ros.transport.step_batch import synchronous_publisher


class ArmTopics:
    """One cell robot's joint topics (see the module's docstring)."""

    def __init__(self, arm, commands, log):
        """``commands``: the cell's :class:`~epuck_vrep_compat.cell.commands.CellCommands`."""
        self.arm = arm
        self._commands = commands
        self._log = log
        robot = ros_robot_name(arm.spec.name)
        self._msg = JointState(name=arm.joint_names())
        self._subscribers = [rospy.Subscriber(JOINT_COMMAND_TOPIC.format(robot=robot), JointState,
                                              self._on_joint_command, queue_size=10)]
        if arm.spec.mobile:
            self._subscribers.append(rospy.Subscriber(BASE_CMD_VEL_TOPIC.format(robot=robot),
                                                      Twist, self._on_cmd_vel, queue_size=10))
        self._states = synchronous_publisher(JOINT_STATES_TOPIC.format(robot=robot), JointState)

    def close(self):
        """The robot was removed: its topics go."""
        self._states.unregister()
        for subscriber in self._subscribers:
            subscriber.unregister()

    def publish(self, batch, stamp):
        """This step's joint states, when someone listens."""
        if batch.wanted(self._states):
            arm, msg = self.arm, self._msg
            msg.header.stamp = stamp
            msg.position = arm.q.tolist()
            msg.velocity = arm.qd.tolist()
            msg.effort = arm.tau.tolist()
            batch.add(self._states, msg)

    def _on_joint_command(self, msg):
        arm = self.arm
        names = list(msg.name) if msg.name else arm.joint_names()
        values, mode = (msg.position, POSITION) if msg.position else (msg.velocity, VELOCITY)
        if len(values) != len(names):
            self._log.warn(f"{arm.spec.name}:lengths",
                           "/%s/joint_command: %d names but %d values; ignored",
                           arm.spec.name, len(names), len(values))
            return
        for refused in self._commands.joints(arm.spec.name, names, values, mode):
            name, value, problem, limit = refused
            if problem == CLAMPED:
                self._log.warn(f"{arm.spec.name}:{name}:speed",
                               "/%s/joint_command: joint '%s' velocity %s clamped to its "
                               "limit %s", arm.spec.name, name, value, limit)
            else:
                self._log.warn(f"{arm.spec.name}:{name}:{problem == UNKNOWN}",
                               "/%s/joint_command: %s joint '%s' value %s; ignored",
                               arm.spec.name, "unknown" if problem == UNKNOWN else "bad", name,
                               value)

    def _on_cmd_vel(self, msg):
        arm = self.arm
        v = (msg.linear.x, msg.linear.y, msg.angular.z)
        applied = self._commands.twist(arm.spec.name, *v)
        if applied is None:
            self._log.warn(f"{arm.spec.name}:cmd_vel", "/%s/cmd_vel: non-finite twist ignored",
                           arm.spec.name)
        elif applied != v:
            self._log.warn(f"{arm.spec.name}:cmd_vel:speed", "/%s/cmd_vel: twist %s scaled to "
                           "%s (the base's top speed)", arm.spec.name,
                           tuple(round(x, 3) for x in v), tuple(round(x, 3) for x in applied))
