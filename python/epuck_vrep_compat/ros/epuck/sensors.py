"""The per-robot topics of a topic profile: sensors out, ``cmd_vel`` in.

Publishing happens once per step from the simulation thread, only for publishers that have a
subscriber (tracked by a subscribe listener, so idle robots cost nothing). Per-step messages go
out synchronously (see ``transport/step_batch.py``). Callbacks only validate and store
commands, by robot name. :meth:`EpuckFace.sync` follows robots added to and removed from the
simulation: a new robot's topics are advertised, a removed robot's unadvertised.
"""

import fnmatch

import numpy as np
import rospy
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Imu, LaserScan, Range

from epuck_vrep_compat.compat import epuck_names
from epuck_vrep_compat.compat.frames import ODOM_FRAME
from epuck_vrep_compat.ros.common.lockstep import StepLockstep
from epuck_vrep_compat.ros.common.log import ThrottledLog
from epuck_vrep_compat.ros.epuck import commands
from epuck_vrep_compat.ros.epuck.drivers import driver_scan
from epuck_vrep_compat.ros.face import Face, Step
from epuck_vrep_compat.ros.transport import wire
from epuck_vrep_compat.ros.transport.step_batch import synchronous_publisher

GRAVITY_SIGN = {"ros": 1.0, "vrep": -1.0}


class _RouteWatch(rospy.SubscribeListener):
    """Marks one robot's routes (where its messages go, see :meth:`EpuckFace.publish`) stale
    whenever a connection to one of its publishers comes or goes."""

    def __init__(self, face):
        super().__init__()
        self._face = face
        self.publishers = []
        self.routes_stale = True

    def _changed(self):
        self.routes_stale = True          # the robot's first, then the face's (see _route)
        self._face.routes_stale = True

    def peer_subscribe(self, topic_name, topic_publish, peer_publish):
        self._changed()

    def peer_unsubscribe(self, topic_name, num_peers):
        self._changed()


class _Robot:
    """One robot's publishers and subscribers."""

    def __init__(self, face, name):
        profile = face.profile
        listener = self.watch = _RouteWatch(face)

        def publisher(role, msg_class):
            pub = synchronous_publisher(profile.topic(name, role), msg_class,
                                        subscriber_listener=listener)
            listener.publishers.append(pub)      # before any subscriber can count on it
            return pub
        self.ranges = [publisher(f"proximity{k}", Range)
                       for k in range(epuck_names.PROXIMITY_COUNT)]
        self.imu = publisher(profile.imu_role, Imu) if profile.imu_role else None
        self.ground_truth = (publisher("ground_truth", Odometry) if face.publish_ground_truth
                             else None)
        self.odom = publisher("odom", Odometry) if profile.publishes_odometry else None
        self.scan = publisher("scan", LaserScan) if profile.publishes_scan else None
        self.scan_frame = profile.frame(name, epuck_names.LASER_FRAME)
        self.cmd_vel = rospy.Subscriber(profile.topic(name, "cmd_vel"), Twist, face.on_cmd_vel,
                                        name, queue_size=10)
        self.outputs = []
        self.routes = []        # (kind, writer id, begin, end) per connection of its outputs

    def close(self):
        """The robot was removed: its topics go."""
        self.cmd_vel.unregister()
        for pub in self.watch.publishers:
            pub.unregister()


class EpuckFace(Face):
    """The per-robot sensor topics (ranges, IMU, odometry, ground truth, the driver's scan) and
    each robot's ``cmd_vel``."""

    def __init__(self, profile, sim, cmd_vel_scaling, accel_sign, publish_ground_truth,
                 lockstep=((), 0.0)):
        """``lockstep``: (cmd_vel topic patterns, timeout in s of wall time); with patterns
        and a timeout > 0, the simulator waits after each step for one ``cmd_vel`` of every
        robot whose topic matches, answering that step (:attr:`lockstep`; see
        :mod:`epuck_vrep_compat.ros.common.lockstep`: no handshake, a controller answers each
        step's sensor messages; a command beyond the steps published answers the next)."""
        self.profile = profile
        self.sim = sim
        self.scaling = cmd_vel_scaling
        self.publish_ground_truth = publish_ground_truth
        self.gravity_sign = GRAVITY_SIGN[accel_sign]
        self._log = ThrottledLog()
        self.robots = []
        self._by_name = {}
        self.routes_stale = True
        self._routes = {}             # kind -> (M, 3) rows for StepBatch.add_slices
        self._routes_batch = None     # the batch whose writer ids the routes hold
        self._scanned = []            # (row, robot) of the robots whose scan has a subscriber
        self._sensor_yaws = [s.yaw_rad for s in sim.epucks.model.sensors]
        self._max_range = profile.range.max_range_m
        self._min_range = profile.range.min_range_m
        patterns, timeout_s = lockstep
        self.lockstep = None                 # None: the simulator does not wait for cmd_vel
        if patterns and timeout_s > 0.0:
            self.lockstep = StepLockstep(
                lambda: [n for n in self._by_name if any(
                    fnmatch.fnmatchcase(profile.topic(n, "cmd_vel"), p) for p in patterns)],
                timeout_s, "cmd_vel", handshake=False, early_answers=True,
                connected=lambda n: n in self._by_name
                and self._by_name[n].cmd_vel.get_num_connections() > 0)
        self.sync()

    def sync(self):
        """Follow the simulation's robots (between steps): topics for each new robot, none for
        each removed one, the rows and message layouts of the ones there are now."""
        names = self.sim.epucks.robot_names
        gone = [r for name, r in self._by_name.items() if name not in names]
        by_name = {name: self._by_name.get(name) or _Robot(self, name) for name in names}
        self.robots = [by_name[name] for name in names]
        self._by_name = by_name
        for robot in gone:
            robot.close()
        self._lay_out(names)

    def _lay_out(self, robots):
        """The pre-serialised messages of every robot, in row order."""
        profile = self.profile
        frame = profile.frame
        rng = profile.range
        self._range_batch = wire.range_batch(
            [frame(r, epuck_names.PROX_FRAME_FORMAT.format(i=k))
             for r in robots for k in range(epuck_names.PROXIMITY_COUNT)],
            Range.INFRARED, rng.field_of_view_rad, rng.min_range_m, rng.max_range_m)
        noise = self.sim.epucks.noise
        self._imu_batch = wire.imu_batch(
            [frame(r, epuck_names.BASE_FRAME) for r in robots],
            np.square(noise.accel_stddev_m_s2) if noise.enabled else np.zeros(3),
            (np.square(noise.gyro_stddev_rad_s) if noise.enabled else np.zeros(3))
            if profile.has_gyro else None)
        self._odom_batch = wire.odometry_batch(ODOM_FRAME,
                                               [frame(r, epuck_names.BASE_FRAME) for r in robots])
        self._wheel_odom_batch = wire.odometry_batch(  # the driver's covariance, if any
            ODOM_FRAME, [frame(r, epuck_names.BASE_FRAME) for r in robots],
            profile.odom_pose_variances)
        for i, robot in enumerate(self.robots):
            robot.outputs = self._outputs(i, robot)
            robot.watch.routes_stale = True
        self.routes_stale = True

    def _outputs(self, i, robot):
        """(publisher, message kind, byte range of its frame in the kind's packed step)."""
        per_robot = epuck_names.PROXIMITY_COUNT
        out = [(pub, "range", self._range_batch.bounds(i * per_robot + k))
               for k, pub in enumerate(robot.ranges)]
        if robot.imu is not None:
            out.append((robot.imu, "imu", self._imu_batch.bounds(i)))
        if robot.ground_truth is not None:
            out.append((robot.ground_truth, "ground_truth", self._odom_batch.bounds(i)))
        if robot.odom is not None:
            out.append((robot.odom, "odom", self._wheel_odom_batch.bounds(i)))
        return out

    # --- commands ------------------------------------------------------------------------
    def on_cmd_vel(self, msg, name):
        model = self.sim.epucks.model
        wheels = commands.wheel_speeds(self.scaling, msg.linear.x, msg.angular.z,
                                       model.wheel_radius_m, model.wheel_separation_m)
        if wheels is None or not self.sim.epucks.set_wheel_speeds(name, *wheels):
            self._log.warn(f"{name}:cmd_vel", "%s: cmd_vel with a non-finite value refused "
                           "(linear.x=%s, angular.z=%s); wheels unchanged", name, msg.linear.x,
                           msg.angular.z)
        if self.lockstep is not None:        # applied (or refused): it answers the step
            self.lockstep.answered(name)

    # --- per step ------------------------------------------------------------------------
    def publish(self, step: Step):
        """Queue this step's sensor messages of every robot someone listens to: each kind
        packed once for all robots, its slices handed to the step batch in one call."""
        batch, secs, nsecs = step.batch, step.secs, step.nsecs
        if self.routes_stale or batch is not self._routes_batch:
            self._route(batch)
        for kind, slices in self._routes.items():
            batch.add_slices(self._pack(kind, secs, nsecs), slices)
        if self._scanned:
            clean = self.sim.epucks.swarm.ranges_clean
            for i, robot in self._scanned:
                batch.add(robot.scan, self._scan(robot, secs, nsecs, clean[i]))

    def _route(self, batch):
        """Where each message goes: for every connection of every output, the batch's writer
        id and the message's bytes in its kind's packed step. Only robots whose connections
        changed are looked at again (all of them for a new batch or layout). The driver's scan
        (a genpy message per robot) goes through :meth:`StepBatch.add` for the robots listed."""
        everything = batch is not self._routes_batch
        self.routes_stale = False     # first: an event from now on marks it again
        self._routes_batch = batch
        rows = {}
        for robot in self.robots:
            watch = robot.watch
            if everything or watch.routes_stale:
                watch.routes_stale = False
                robot.routes = [(kind, wid, start, end)
                                for pub, kind, (start, end) in robot.outputs
                                for connection in pub.impl.connections
                                for wid in (batch.writer_id(pub, connection),)
                                if wid is not None]
            for kind, wid, start, end in robot.routes:
                rows.setdefault(kind, []).append((wid, start, end))
        self._routes = {kind: np.array(r, dtype=np.int64) for kind, r in rows.items()}
        self._scanned = [(i, robot) for i, robot in enumerate(self.robots)
                         if robot.scan is not None and robot.scan.impl.connections]

    def _pack(self, kind, secs, nsecs) -> np.ndarray:
        """This step's messages of one kind for all robots, in the kind's own buffer (valid
        until its next pack; the step batch copies the slices at once)."""
        swarm = self.sim.epucks.swarm
        if kind == "range":
            ranges = np.clip(swarm.ranges, self._min_range, self._max_range)
            return self._range_batch.pack_view(secs, nsecs, range=ranges)
        if kind == "imu":
            gyro = swarm.gyro if self.profile.has_gyro else np.zeros((swarm.size, 3))
            return self._imu_batch.pack_view(secs, nsecs, accel=swarm.accel * self.gravity_sign,
                                        gyro=gyro)
        if kind == "ground_truth":
            poses, velocities = swarm.poses, swarm.velocities
            # contiguous: numpy 1.24 takes its vector cos/sin for a strided column only when
            # the result happens to lie far enough from it in memory (libm's otherwise, 1 ulp
            # apart), which made identical runs' forward speeds differ in the last bit
            yaw = np.ascontiguousarray(poses[:, 2])
            forward = velocities[:, 0] * np.cos(yaw) + velocities[:, 1] * np.sin(yaw)
            return self._odom_batch.pack_view(secs, nsecs, **wire.planar_odometry_values(
                poses[:, 0], poses[:, 1], yaw, forward, velocities[:, 2]))
        odometry = swarm.odometry
        return self._wheel_odom_batch.pack_view(secs, nsecs, **wire.planar_odometry_values(
            *(odometry[:, k] for k in range(5))))

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
