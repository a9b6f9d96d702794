"""``operator_tracker``: where the operator is, fused from the cell's sensors; a client of the
simulator's topics only (as the thesis's nodes are).

- The two ceiling cameras' blob positions (``/vrep/Blob_Camera_k_X|Y``), through the thesis's
  calibration (:mod:`tracker_geometry`): both fresh, their rays are triangulated; one alone, its
  ray is cut at the silhouette's mid-height (a larger noise).
- The laser (``/vrep/front_scan``, placed by TF): of the returns short of the background, the
  person-sized cluster nearest the cameras' estimate (the filter's prediction while no camera
  sees him).
- The Kinect (``/kinect/depth/image`` from the thesis's ``[/kinect]`` node, placed by TF): the
  depth about the estimate's projection, a range along its ray (:mod:`tracker_kinect`).
- A constant-velocity Kalman filter (:mod:`tracker_filter`) fuses them with each sensor's
  noise, so the track goes on while a sensor loses the operator (out of a camera's view, behind
  the table for the laser), its covariance growing.

Published (``~rate_hz``, simulated time, in ``world``): ``~pose``
(``geometry_msgs/PoseWithCovarianceStamped``), ``~twist``
(``geometry_msgs/TwistWithCovarianceStamped``), ``~markers`` (the estimate and its 2-sigma
ellipse). Parameters: ``~rate_hz`` (20), ``~camera0_matrix``, ``~camera1_matrix`` (the
thesis's), ``~view_angle_deg`` (80), ``~blob_height_m`` (0.6), ``~camera_pair_sigma_m``
(0.08), ``~camera_single_sigma_m`` (0.35), ``~laser_sigma_m`` (0.06), ``~laser_gate_m`` (0.8),
``~fresh_s`` (0.15: older blobs are not used), ``~accel_density`` (4 m^2/s^3),
``~kinect_fov_deg`` (57), ``~bias_sigma_m`` (0.05) and ``~lag_s`` (0.05): the published
position covariance is the filter's plus the sensors' biases and the lag
(:func:`tracker_filter.published_covariance`, measured in docs/cell.md). With ``~lockstep``
(false) it estimates once per simulation step instead, from that step's inputs
(:mod:`tracker_steps`: ``~laser_period_s``, ``~kinect_period_s``). ``~reset``
(``std_srvs/Trigger``, :mod:`node_reset`): as launched, for the next run of one launch.
"""
import numpy as np
import rospy
import tf2_ros
from geometry_msgs.msg import PoseWithCovarianceStamped, TwistWithCovarianceStamped
from sensor_msgs.msg import Image, LaserScan
from std_msgs.msg import Float32
from visualization_msgs.msg import MarkerArray

from epuck_vrep_compat.compat.frames import WORLD_FRAME
from epuck_vrep_compat.compat.topics import (
    BLOB_TOPIC_FORMAT, CELL_LASER_TOPIC, KINECT_DEPTH_IMAGE_TOPIC, NODE_NAMESPACE)
from epuck_vrep_compat.nodes import tracker_geometry as geo
from epuck_vrep_compat.nodes.tracker_filter import OperatorFilter, published_covariance
from epuck_vrep_compat.nodes.tracker_kinect import KinectRange
from epuck_vrep_compat.nodes.node_reset import ResetService, clear_tf, restart_ros_time
from epuck_vrep_compat.nodes.step_inputs import Inbox, NotifyingTransformListener
from epuck_vrep_compat.nodes.tracker_markers import estimate_markers
from epuck_vrep_compat.nodes.tracker_steps import TrackerSteps
from epuck_vrep_compat.ros.common.log import ThrottledLog
from epuck_vrep_compat.ros.common.params import ParamError, read_typed


LOST_AFTER = 10          # cycles of refused camera measurements before the track restarts


def _positive(name, default):
    return read_typed(name, default, float, lambda v: v > 0, "must be > 0")


def _non_negative(name, default):
    return read_typed(name, default, float, lambda v: v >= 0, "must be >= 0")


def _matrix(name, default):
    value = rospy.get_param("~" + name, list(default))
    if (not isinstance(value, (list, tuple)) or len(value) != 12
            or not all(isinstance(v, (int, float)) for v in value)):
        raise ParamError(f"parameter '~{name}' must be 12 numbers (rows of [R | t])")
    return value


class OperatorTracker:
    """The node's state: the latest blob per camera, the latest scan, the filter."""

    def __init__(self):
        angle = _positive("view_angle_deg", geo.VIEW_ANGLE_DEG)
        self.cameras = [geo.BlobCamera(_matrix(f"camera{k}_matrix", m), angle)
                        for k, m in enumerate(geo.THESIS_CAMERA_MATRICES)]
        self.blob_height = _positive("blob_height_m", geo.BLOB_HEIGHT_M)
        self.sigma = {k: _positive(f"{k}_sigma_m", d) for k, d in
                      (("camera_pair", 0.08), ("camera_single", 0.35), ("laser", 0.06))}
        self.laser_gate = _positive("laser_gate_m", 0.8)
        self.bias_sigma = _non_negative("bias_sigma_m", 0.05)
        self.lag_s = _non_negative("lag_s", 0.05)
        self.fresh_s = _positive("fresh_s", 0.15)
        self.rate_hz = rate_hz = _positive("rate_hz", 20.0)
        self.lockstep = read_typed("lockstep", False, bool)
        self.accel_density = _positive("accel_density", 4.0)
        self.scan, self.depth = Inbox(), Inbox()        # the newest, not used yet
        self.kinect = KinectRange(_positive("kinect_fov_deg", 57.0))
        self.start_state()
        self.tf = tf2_ros.Buffer()
        self._listener = NotifyingTransformListener(self.tf)
        # in lock-step the blobs are read from /vrep at each step (their topics carry no stamp)
        self._subs = [] if self.lockstep else [
            rospy.Subscriber(BLOB_TOPIC_FORMAT.format(camera=k, axis=a), Float32, self._on_blob,
                             (k, a), queue_size=4) for (k, a) in self.blobs]
        self.scan_sub = rospy.Subscriber(NODE_NAMESPACE + CELL_LASER_TOPIC, LaserScan,
                                         self.scan.put, queue_size=1)
        self.depth_sub = rospy.Subscriber(KINECT_DEPTH_IMAGE_TOPIC, Image, self._on_depth,
                                          queue_size=1, buff_size=2 ** 22)
        queue = 10 if self.lockstep else 1      # lock-step: every step's estimate, latched
        self.pose_pub = rospy.Publisher("~pose", PoseWithCovarianceStamped, queue_size=queue,
                                        latch=self.lockstep)
        self.twist_pub = rospy.Publisher("~twist", TwistWithCovarianceStamped, queue_size=queue)
        self.marker_pub = rospy.Publisher("~markers", MarkerArray, queue_size=1)
        rospy.loginfo("operator_tracker: %s; sigmas %s m; laser gate %.2f m",
                      "in lock-step" if self.lockstep else f"{rate_hz} Hz", self.sigma,
                      self.laser_gate)
        if self.lockstep:
            self.steps = TrackerSteps(self, _non_negative("laser_period_s", 0.1),
                                      _non_negative("kinect_period_s", 0.1))
        else:
            self.timer = rospy.Timer(rospy.Duration(1.0 / rate_hz), self.cycle)

    def start_state(self):
        """What a run changes, as at the start: no blob, no scan or image waiting, no track."""
        self.log = ThrottledLog()
        self.blobs = {(k, a): None for k in range(2) for a in "XY"}
        self.scan.reset()
        self.depth.reset()
        self.filter = OperatorFilter(self.accel_density)
        self.background = geo.LaserBackground()
        self.refused = 0          # camera measurements refused in a row: the track is lost

    def reset(self):
        """``~reset``: as launched (the simulator rewound, paused before its first step); in
        lock-step the ready message again, else the timer from the clock's 0."""
        restart_ros_time()
        clear_tf(self._listener)
        self.start_state()
        if self.lockstep:
            self.steps.restart()
        else:
            self.timer.shutdown()
            self.timer = rospy.Timer(rospy.Duration(1.0 / self.rate_hz), self.cycle)

    def _on_blob(self, msg, key):
        self.blobs[key] = (rospy.Time.now().to_sec(), float(msg.data))

    def _on_depth(self, msg):
        if msg.encoding == "32FC1":
            self.depth.put(msg)

    def _sensor_pose(self, frame):
        """(position, quaternion) of a sensor frame in the world, or None (warned); in
        lock-step once it is known (its static frame may come after the first step)."""
        if self.lockstep:
            self._listener.wait_transform(WORLD_FRAME, frame, rospy.Time(0))
        try:
            t = self.tf.lookup_transform(WORLD_FRAME, frame, rospy.Time(0)).transform
        except (tf2_ros.LookupException, tf2_ros.ConnectivityException,
                tf2_ros.ExtrapolationException) as error:
            self.log.warn(f"tf:{frame}", "operator_tracker: no pose of %s: %s", frame, error)
            return None
        p, q = t.translation, t.rotation
        return np.array([p.x, p.y, p.z]), np.array([q.x, q.y, q.z, q.w])

    def kinect_measurement(self):
        """(xy, R): the Kinect's range to him along its ray, in an image not used yet."""
        msg = self.depth.take()
        if msg is None or not self.filter.started:
            return None
        pose = self._sensor_pose(msg.header.frame_id)
        if pose is None:
            return None
        depth = np.frombuffer(msg.data, dtype="<f4" if not msg.is_bigendian else ">f4")
        if depth.size != msg.height * msg.width:
            self.log.warn("kinect:size", "operator_tracker: depth image of the wrong size")
            return None
        depth = depth.reshape(msg.height, msg.width)
        return self.kinect.measurement(depth, *pose, self.filter.x[:2])

    def camera_measurement(self, now):
        """(xy, R) from the cameras with a fresh blob, or None."""
        seen = []
        for k, camera in enumerate(self.cameras):
            x, y = self.blobs[(k, "X")], self.blobs[(k, "Y")]
            if x is None or y is None or now - min(x[0], y[0]) > self.fresh_s:
                continue
            if np.isfinite(x[1]) and np.isfinite(y[1]):
                seen.append((camera, x[1], y[1]))
        if len(seen) == 2:
            point = geo.triangulate([c.centre for c, _, _ in seen],
                                    [c.ray(u, v) for c, u, v in seen])
            if point is not None:
                return point[:2], np.eye(2) * self.sigma["camera_pair"] ** 2
        if seen:
            camera, u, v = seen[0]
            xy = camera.at_height(u, v, self.blob_height)
            if xy is not None:
                return xy, np.eye(2) * self.sigma["camera_single"] ** 2
        return None

    def laser_measurement(self, camera):
        """(xy, R) of the cluster, in a scan not used yet, nearest the cameras' estimate (or,
        while no camera sees him, the filter's prediction); None without one."""
        scan = self.scan.take()
        if scan is None:
            return None
        pose = self._sensor_pose(scan.header.frame_id)
        if pose is None:
            return None
        position, quat = pose
        points = geo.scan_points(self.background.foreground(scan.ranges), scan.angle_min,
                                 scan.angle_increment, position, quat)
        candidates = geo.person_candidates(points, position[:2])
        if camera is not None:
            reference = camera[0]
        elif self.filter.started:
            reference = self.filter.x[:2]
        else:
            return None
        best, _ = geo.nearest(candidates, reference, self.laser_gate)
        return None if best is None else (best, np.eye(2) * self.sigma["laser"] ** 2)

    def cycle(self, _event=None, now=None):
        """One estimate at ``now`` (None: the clock's time); False when there is none (no
        track yet and no camera sees him)."""
        now = now if now is not None else rospy.Time.now()
        t = now.to_sec()
        camera = self.camera_measurement(t)
        laser = self.laser_measurement(camera)    # (keeps the background up to date)
        if self.refused >= LOST_AFTER:
            self.log.warn("lost", "operator_tracker: the cameras disagree with the track; "
                          "restarting from them")
            self.filter.x, self.refused = None, 0
        if not self.filter.started:
            if camera is None:
                return False
            self.filter.start(t, *camera)
        self.filter.predict(t)
        if camera is not None:
            self.refused = 0 if self.filter.update(*camera) else self.refused + 1
        for measurement in (laser, self.kinect_measurement()):
            if measurement is not None:
                self.filter.update(*measurement)
        self.publish(now)
        return True

    def publish(self, stamp):
        """The filter's estimate; without a track (lock-step's every step must have its
        message), a position and covariance of NaN."""
        if self.filter.started:
            x, cov = self.filter.x, self.filter.P
        else:
            x, cov = np.full(4, np.nan), np.full((4, 4), np.nan)
        pose = PoseWithCovarianceStamped()
        pose.header.stamp, pose.header.frame_id = stamp, WORLD_FRAME
        pose.pose.pose.position.x, pose.pose.pose.position.y = float(x[0]), float(x[1])
        pose.pose.pose.orientation.w = 1.0
        twist = TwistWithCovarianceStamped()
        twist.header = pose.header
        twist.twist.twist.linear.x, twist.twist.twist.linear.y = float(x[2]), float(x[3])
        pc, tc = np.zeros((6, 6)), np.zeros((6, 6))
        pc[:2, :2] = published_covariance(cov, x, self.bias_sigma, self.lag_s)
        tc[:2, :2] = cov[2:, 2:]
        pc[2, 2] = pc[3, 3] = pc[4, 4] = pc[5, 5] = 1e6      # z and rotations: not estimated
        tc[2, 2] = tc[3, 3] = tc[4, 4] = tc[5, 5] = 1e6
        pose.pose.covariance, twist.twist.covariance = pc.ravel().tolist(), tc.ravel().tolist()
        self.pose_pub.publish(pose)
        self.twist_pub.publish(twist)
        if self.filter.started:
            self.marker_pub.publish(MarkerArray(markers=estimate_markers(
                WORLD_FRAME, stamp, x, pc[:2, :2])))


def main():
    rospy.init_node("operator_tracker")
    try:
        ResetService(OperatorTracker().reset)
    except ParamError as error:
        rospy.logfatal("operator_tracker: %s", error)
        return 2
    rospy.spin()
    return 0
