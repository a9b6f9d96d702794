"""The per-robot topics of a topic profile: sensors out, ``cmd_vel`` and ``cmd_led`` in.

Publishing happens once per step from the simulation thread, only for publishers that have a
subscriber (tracked by a subscribe listener, so idle robots cost nothing). Per-step messages go
out synchronously (see ``publishing.py``). Callbacks only validate and store commands.
"""
import math

import numpy as np
import rospy
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Imu, LaserScan, Range

from epuck_vrep_compat.ros import commands, driver_scan, names
from epuck_vrep_compat.ros.publishing import synchronous_publisher
from epuck_vrep_compat.ros.wire import ImuWire, OdometryWire, RangeWire

GRAVITY_SIGN = {"ros": 1.0, "vrep": -1.0}


class _ConnectionCounter(rospy.SubscribeListener):
    """Counts subscriber connections of one robot's publishers."""

    def __init__(self, counts, index):
        super().__init__()
        self._counts = counts
        self._index = index

    def peer_subscribe(self, topic_name, topic_publish, peer_publish):
        self._counts[self._index] += 1

    def peer_unsubscribe(self, topic_name, num_peers):
        self._counts[self._index] = max(0, self._counts[self._index] - 1)


class _Robot:
    def __init__(self, face, index, name):
        profile = face.profile
        listener = _ConnectionCounter(face.connections, index)

        def publisher(role, msg_class):
            return synchronous_publisher(profile.topic(name, role), msg_class,
                                         subscriber_listener=listener)
        topic = lambda role: profile.topic(name, role)  # noqa: E731
        frame = lambda f: profile.frame(name, f)  # noqa: E731
        rng = profile.range
        self.ranges = [publisher(f"proximity{k}", Range) for k in range(names.PROXIMITY_COUNT)]
        self.range_wires = [RangeWire(frame(names.PROX_FRAME_FORMAT.format(i=k)),
                                      Range.INFRARED, rng.field_of_view_rad, rng.min_range_m,
                                      rng.max_range_m) for k in range(names.PROXIMITY_COUNT)]
        self.imu = publisher(profile.imu_role, Imu)
        self.imu_wire = ImuWire(frame(names.BASE_FRAME),
                                orientation_known=profile.name == "epuck_driver")
        self.ground_truth = None
        if face.publish_ground_truth:
            self.ground_truth = publisher("ground_truth", Odometry)
        self.ground_truth_wire = OdometryWire(names.ODOM_FRAME, frame(names.BASE_FRAME))
        self.odom = self.scan = None
        if profile.publishes_odometry:
            self.odom = publisher("odom", Odometry)
        if profile.publishes_scan:
            self.scan = publisher("scan", LaserScan)
            self.scan_frame = frame(names.LASER_FRAME)
        self.cmd_vel = rospy.Subscriber(topic("cmd_vel"), Twist, face.on_cmd_vel, index,
                                        queue_size=10)


class EpuckFace:
    def __init__(self, profile, sim, cmd_vel_scaling, accel_sign, publish_ground_truth, leds):
        self.profile = profile
        self.sim = sim
        self.scaling = cmd_vel_scaling
        self.publish_ground_truth = publish_ground_truth
        self.gravity_sign = GRAVITY_SIGN[accel_sign]
        self.connections = np.zeros(sim.size, dtype=np.int64)
        self.robots = [_Robot(self, i, name) for i, name in enumerate(sim.robot_names)]
        self.leds = leds
        self._sensor_yaws = [s.yaw_rad for s in sim.model.sensors]
        self._max_range = profile.range.max_range_m
        self._min_range = profile.range.min_range_m

    # --- commands ------------------------------------------------------------------------
    def on_cmd_vel(self, msg, index):
        model = self.sim.model
        wheels = commands.wheel_speeds(self.scaling, msg.linear.x, msg.angular.z,
                                       model.wheel_radius_m, model.wheel_separation_m)
        if wheels is None or not self.sim.set_wheel_speeds(index, *wheels):
            rospy.logwarn_throttle(
                5.0, f"{self.sim.robot_names[index]}: cmd_vel with a non-finite value refused "
                     f"(linear.x={msg.linear.x}, angular.z={msg.angular.z}); wheels unchanged")

    # --- per step ------------------------------------------------------------------------
    def publish(self, secs: int, nsecs: int):
        active = np.flatnonzero(self.connections)
        if active.size == 0:
            return
        swarm = self.sim.swarm
        ranges = np.clip(swarm.ranges, self._min_range, self._max_range)
        accel = swarm.accel * self.gravity_sign
        gyro = swarm.gyro if self.profile.name != "epuck_driver" else np.zeros_like(swarm.gyro)
        poses = swarm.poses
        velocities = swarm.velocities
        odometry = swarm.odometry if self.profile.publishes_odometry else None
        for i in active:
            robot = self.robots[i]
            row = ranges[i]
            for k, pub in enumerate(robot.ranges):
                if pub.impl.has_connections():
                    pub.publish(robot.range_wires[k].pack(secs, nsecs, float(row[k])))
            if robot.imu.impl.has_connections():
                robot.imu.publish(robot.imu_wire.pack(secs, nsecs, accel[i], gyro[i]))
            if robot.ground_truth is not None and robot.ground_truth.impl.has_connections():
                x, y, yaw = poses[i]
                vx, vy, wz = velocities[i]
                v = vx * math.cos(yaw) + vy * math.sin(yaw)
                robot.ground_truth.publish(
                    robot.ground_truth_wire.pack(secs, nsecs, x, y, yaw, v, wz))
            if robot.odom is not None and robot.odom.impl.has_connections():
                robot.odom.publish(robot.ground_truth_wire.pack(secs, nsecs, *odometry[i]))
            if robot.scan is not None and robot.scan.impl.has_connections():
                robot.scan.publish(self._scan(robot, secs, nsecs, swarm.ranges_clean[i]))

    def _scan(self, robot, secs, nsecs, ranges):
        values, intensities = driver_scan.scan_from_ranges(ranges, self._max_range,
                                                           self._sensor_yaws)
        msg = LaserScan()
        msg.header.stamp = rospy.Time(secs, nsecs)
        msg.header.frame_id = robot.scan_frame
        msg.angle_min, msg.angle_max = driver_scan.ANGLE_MIN, driver_scan.ANGLE_MAX
        msg.angle_increment = driver_scan.ANGLE_INCREMENT
        msg.range_min, msg.range_max = driver_scan.RANGE_MIN, driver_scan.RANGE_MAX
        msg.ranges = values.tolist()
        msg.intensities = intensities.tolist()
        return msg
