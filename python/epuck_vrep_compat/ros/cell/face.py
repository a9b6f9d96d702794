"""The cell's face: what V-REP's cell scene published through its models' scripts.

- ``/vrep/<laser topic>`` (``sensor_msgs/LaserScan``, default ``/vrep/front_scan``) at the
  scanner's rate, as V-REP's ROS-enabled Hokuyo model did, with the real URG-04LX-UG01's angles,
  step count and range limits; its frame is the scanner's object name.
- TF: ``world -> <object>`` every step for every link of the cell's robots, the operator, the
  scanner, the cameras and the Kinect's sensors (frames are V-REP object names).
- The ceiling cameras' blob positions, exactly as the thesis's child script did it: each step
  the camera's blob x and y become float signals, and publishers of those signals
  (``simros_strmcmd_get_float_signal``) are enabled through the plugin's stream machinery when
  the simulation starts: ``/vrep/Blob_Camera_0_X`` ... They publish only while the operator is
  in view (V-REP's blob filter returns no blob otherwise).
- Per robot: ``/<robot>/joint_states`` (``sensor_msgs/JointState``) every step;
  ``/<robot>/joint_command`` (``sensor_msgs/JointState``: positions are target positions, or,
  with no positions, velocities are target velocities; names select joints, none = all in
  order); ``/<robot>/cmd_vel`` (``geometry_msgs/Twist``) for a mobile base. A command stops
  the robot's default script until the simulation is stopped or reset.
- For rviz: ``/<robot>/robot_description`` (the robot's URDF, links named as their TF frames,
  so a RobotModel display draws each arm from TF alone); ``/vrep/cell_markers`` (latched,
  frame-locked markers for the operator, the laser, the cameras and the Kinect); a static
  ``world -> odom`` identity, so the scene's static objects (``/vrep/markers``, in ``odom``)
  and any e-puck join the cell's tree.
"""
import math

import numpy as np
import rospy
import tf2_ros
from geometry_msgs.msg import TransformStamped, Twist
from sensor_msgs.msg import JointState, LaserScan
from std_msgs.msg import ColorRGBA
from visualization_msgs.msg import Marker, MarkerArray
from vrep_common.srv import simRosEnablePublisherRequest

from epuck_vrep_compat.cell.articulated import POSITION, VELOCITY
from epuck_vrep_compat.ros.common.log import ThrottledLog
from epuck_vrep_compat.ros.common.names import NODE_NAMESPACE, ODOM_FRAME
from epuck_vrep_compat.ros.face import Face, Step
from epuck_vrep_compat.ros.messages import shape_marker
from epuck_vrep_compat.ros.transport.step_batch import synchronous_publisher
from epuck_vrep_compat.ros.transport.wire import TransformBatchWire
from epuck_vrep_compat.sim.control import STOPPED
from epuck_vrep_compat.vrep import constants as vc

WORLD_FRAME = "world"
CELL_MARKER_TOPIC = NODE_NAMESPACE + "cell_markers"
_DEVICE_COLOR = ColorRGBA(0.15, 0.15, 0.15, 1.0)


class CellFace(Face):
    """The industrial cell: joint states and commands, the laser scan, the cell's TF, the blob
    signal streams, robot descriptions and markers for rviz."""

    def __init__(self, sim, vrep_face, lock):
        self.sim = sim
        self.cell = sim.cell
        self._streams = vrep_face.streams
        self._backend = vrep_face.backend
        self._lock = lock
        self._blob_enabled = False
        self._log = ThrottledLog()
        self._backend.control.listeners.append(self._on_state)
        cell = self.cell
        self._scan = None
        if cell.laser is not None:
            self._scan = synchronous_publisher("~" + cell.laser.topic, LaserScan)
            self._scan_msg = self._laser_message()
        self._arms = {}                     # robot name -> (publisher, arm, msg, subscribers)
        for arm in cell.arms:
            ns = "/" + arm.spec.name
            msg = JointState(name=arm.joint_names())
            subscribers = [rospy.Subscriber(ns + "/joint_command", JointState,
                                            self._on_joint_command, arm, queue_size=10)]
            if arm.spec.mobile:
                subscribers.append(rospy.Subscriber(ns + "/cmd_vel", Twist, self._on_cmd_vel,
                                                    arm, queue_size=10))
            self._arms[arm.spec.name] = (synchronous_publisher(ns + "/joint_states",
                                                               JointState), arm, msg, subscribers)
        self._blob_topics = self._camera_blob_topics()
        self._index_tf()
        self._publish_for_rviz()

    def _index_tf(self):
        self._tf_objects = self._tf_frames()
        self._tf_wire = TransformBatchWire([(WORLD_FRAME, name) for name, _ in
                                            self._tf_objects])

    def _camera_blob_topics(self):
        return {t for c in self.cell.camera_specs for t in c.blob_topics}

    def sync(self):
        """Follow the cell's objects after a removal (between steps, under the lock): the
        removed robots' topics and descriptions, the laser's topic, the removed cameras' blob
        signals and their TF frames go; the markers are re-sent."""
        for name in [n for n in self._arms if n not in self.cell.arm_by_name]:
            publisher, _, _, subscribers = self._arms.pop(name)
            publisher.unregister()
            for subscriber in subscribers:
                subscriber.unregister()
            if rospy.has_param("/" + name + "/robot_description"):
                rospy.delete_param("/" + name + "/robot_description")
        if self._scan is not None and self.cell.laser is None:
            self._scan.unregister()
            self._scan = None
        blob_topics = self._camera_blob_topics()
        for topic in self._blob_topics - blob_topics:
            self._backend.clear_signal("float", topic)
        self._blob_topics = blob_topics
        self._index_tf()
        self._markers.publish(self._marker_array())

    # --- rviz: robot descriptions, markers, the static world -> odom -------------------------
    def _publish_for_rviz(self):
        for arm in self.cell.arms:
            rospy.set_param("/" + arm.spec.name + "/robot_description", arm.description())
        self._static_tf = tf2_ros.StaticTransformBroadcaster()
        odom = TransformStamped()
        odom.header.frame_id = WORLD_FRAME
        odom.child_frame_id = ODOM_FRAME
        odom.transform.rotation.w = 1.0
        self._static_tf.sendTransform(odom)
        self._markers = rospy.Publisher(CELL_MARKER_TOPIC, MarkerArray, queue_size=1,
                                        latch=True)
        self._markers.publish(self._marker_array())

    def _marker_array(self):
        cell, registry = self.cell, self.sim.registry
        out = MarkerArray()
        if cell.operator is not None:
            o = cell.operator.spec
            r, g, b = o.color
            color = ColorRGBA(r, g, b, 1.0)
            frame = registry.get(cell.operator_handles[0]).name
            out.markers.append(shape_marker(
                frame, "operator", 0, Marker.CYLINDER, (0, 0, cell.operator.body_centre_z),
                (2 * o.body_radius_m, 2 * o.body_radius_m, o.body_height_m), color))
            out.markers.append(shape_marker(
                frame, "operator", 1, Marker.SPHERE, (0, 0, cell.operator.head_centre_z),
                (2 * o.head_radius_m,) * 3, color))
        devices = []
        if cell.laser is not None:        # the URG's body: 50 x 50 x 70 mm
            devices.append((cell.laser_handle, Marker.CYLINDER, (0.05, 0.05, 0.07)))
        devices += [(c.handle, Marker.CUBE, (0.08, 0.08, 0.08)) for c in cell.cameras]
        devices += [(v.handle, Marker.CUBE, (0.07, 0.07, 0.07))
                    for v in (cell.kinect_depth, cell.kinect_rgb) if v is not None]
        for handle, shape, size in devices:
            out.markers.append(shape_marker(registry.get(handle).name, "devices", handle, shape,
                                            (0, 0, 0), size, _DEVICE_COLOR))
        return out

    # --- TF -----------------------------------------------------------------------------
    def _tf_frames(self):
        """[(frame, source)]: source is a row of the stacked link poses, or a handle."""
        out = []
        row = 0
        for arm in self.cell.arms:
            for link in arm.link_names:
                out.append((arm.objects[link].name, ("row", row)))
                row += 1
        registry = self.sim.registry
        extra = []
        if self.cell.operator is not None:
            extra.append(self.cell.operator_handles[0])
        if self.cell.laser is not None:
            extra.append(self.cell.laser_handle)
        extra += [c.handle for c in self.cell.cameras]
        extra += [v.handle for v in (self.cell.kinect_depth, self.cell.kinect_rgb)
                  if v is not None]
        out += [(registry.get(h).name, ("handle", h)) for h in extra]
        return out

    def tf_message(self, secs, nsecs):
        positions, quats = self.cell.link_poses()
        t = np.empty((len(self._tf_objects), 3))
        r = np.empty((len(self._tf_objects), 4))
        n = len(positions)
        t[:n], r[:n] = positions, quats
        for i, (_, (kind, h)) in enumerate(self._tf_objects[n:], start=n):
            t[i], r[i] = self.sim.registry.world_pose(h)
        return self._tf_wire.pack(secs, nsecs, t, r)

    # --- laser --------------------------------------------------------------------------
    def _laser_message(self):
        s = self.cell.laser
        msg = LaserScan()
        msg.header.frame_id = s.name
        msg.angle_min = s.angle_min_rad
        msg.angle_increment = s.angle_increment_rad
        msg.angle_max = s.angle_min_rad + (s.count - 1) * s.angle_increment_rad
        msg.scan_time = 1.0 / s.rate_hz
        # a 600 rpm mirror sweeps one step of 2*pi/1024 in scan_time/1024... of a full turn
        msg.time_increment = msg.scan_time * s.angle_increment_rad / (2.0 * math.pi)
        msg.range_min = s.range_min_m
        msg.range_max = s.range_max_m
        return msg

    # --- commands (subscriber threads) -----------------------------------------------------
    def _on_joint_command(self, msg, arm):
        names = list(msg.name) if msg.name else arm.joint_names()
        values, mode = (msg.position, POSITION) if msg.position else (msg.velocity, VELOCITY)
        if len(values) != len(names):
            self._log.warn(f"{arm.spec.name}:lengths",
                           "/%s/joint_command: %d names but %d values; ignored",
                           arm.spec.name, len(names), len(values))
            return
        with self._lock:
            for name, value in zip(names, values):
                k = arm.movable_index(name)
                if k is None or not math.isfinite(value):
                    self._log.warn(f"{arm.spec.name}:{name}:{k is None}",
                                   "/%s/joint_command: %s joint '%s' value %s; ignored",
                                   arm.spec.name, "unknown" if k is None else "bad", name,
                                   value)
                    continue
                joint = arm.joints[k]
                if mode == POSITION:
                    joint.set_target_position(value)
                elif joint.set_target_velocity(value) != value:
                    self._log.warn(f"{arm.spec.name}:{name}:speed",
                                   "/%s/joint_command: joint '%s' velocity %s clamped to its "
                                   "limit %s", arm.spec.name, name, value, joint.max_velocity)

    def _on_cmd_vel(self, msg, arm):
        v = (msg.linear.x, msg.linear.y, msg.angular.z)
        if not all(math.isfinite(x) for x in v):
            self._log.warn(f"{arm.spec.name}:cmd_vel", "/%s/cmd_vel: non-finite twist ignored",
                           arm.spec.name)
            return
        with self._lock:
            applied = arm.set_twist(*v)
        if applied != v:
            self._log.warn(f"{arm.spec.name}:cmd_vel:speed", "/%s/cmd_vel: twist %s scaled to "
                           "%s (the base's top speed)", arm.spec.name,
                           tuple(round(x, 3) for x in v), tuple(round(x, 3) for x in applied))

    # --- per step ------------------------------------------------------------------------
    def _on_state(self, state):
        if state == STOPPED:
            self._blob_enabled = False       # V-REP removes every stream at the end

    def _enable_blob_streams(self):
        """The thesis's child script, first pass: enable the float-signal publishers."""
        for camera in self.cell.camera_specs:
            for topic in camera.blob_topics:
                req = simRosEnablePublisherRequest(topicName=topic, queueSize=1,
                                                   streamCmd=vc.STRMCMD_GET_FLOAT_SIGNAL,
                                                   auxInt1=-1, auxInt2=-1, auxString=topic)
                self._streams.enable_publisher(req)
        self._blob_enabled = True

    def _signals(self):
        """After the step, before ``/vrep``'s streams publish: the scripts' signals."""
        if not self._blob_enabled and self._backend.running:
            self._enable_blob_streams()
        for camera in self.cell.camera_specs:
            if not camera.blob_topics:
                continue
            packet = self.cell.blobs.get(camera.name)
            x_topic, y_topic = camera.blob_topics
            if packet is not None and len(packet) > 6 and packet[0] >= 1:
                self._backend.set_signal("float", x_topic, float(packet[4]))
                self._backend.set_signal("float", y_topic, float(packet[5]))
            else:
                self._backend.clear_signal("float", x_topic)
                self._backend.clear_signal("float", y_topic)

    def publish(self, step: Step):
        """The blob signals (before ``/vrep``'s streams publish them), TF, the laser scan when
        one was taken, the joint states."""
        self._signals()
        batch, stamp = step.batch, step.stamp
        if batch.wanted(step.tf):
            batch.add(step.tf, self.tf_message(step.secs, step.nsecs))
        if self._scan is not None and self.cell.scan_due:
            self.cell.scan_due = False
            if batch.wanted(self._scan):
                msg = self._scan_msg
                msg.header.stamp = stamp
                msg.ranges = self.cell.laser_ranges.tolist()
                batch.add(self._scan, msg)
        for pub, arm, msg, _ in self._arms.values():
            if batch.wanted(pub):
                msg.header.stamp = stamp
                msg.position = arm.q.tolist()
                msg.velocity = arm.qd.tolist()
                msg.effort = arm.tau.tolist()
                batch.add(pub, msg)
