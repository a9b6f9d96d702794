"""Every compatibility name of the e-puck topic profiles, defined once.

Profile ``vrep`` reproduces the V-REP e-puck model (andrei91ro/epuck_vrep_ros.lua): absolute
topics ``/ePuckK/...``, frames ``ePuckK/...`` under a shared ``odom``.
Profile ``epuck_driver`` reproduces the real robot's driver (gctronic/epuck_driver_cpp, the
``multi_epuck.launch`` layout): namespace ``epuck_robot_K``, commands under ``mobile_base/``.
Profile ``epuck2_driver`` reproduces the e-puck2's (the same repository, branch ``e-puck2``,
``epuck2_driver_cpp.cpp`` and ``multi_epuck2.launch``): the same layout, an ``imu``, the
time-of-flight sensor, magnetometer, battery, ground sensors, microphones and RGB LEDs.
"""
from dataclasses import dataclass
from typing import Dict, Optional, Tuple

from epuck_vrep_compat.ros.common.names import ODOM_FRAME  # noqa: F401 (a profile name too)
PROXIMITY_COUNT = 8
ROOT_NAMESPACE = "/"     # a robot name: its topics at the root, as a driver's single-robot launch


@dataclass(frozen=True)
class RangeProfile:
    """Fixed fields of the ``sensor_msgs/Range`` messages a profile publishes."""

    field_of_view_rad: float
    min_range_m: float
    max_range_m: float


@dataclass(frozen=True)
class TopicProfile:
    """Names and message conventions of one face of a simulated e-puck."""

    name: str
    robot_name_format: str          # robot index -> robot name
    topic_prefix_format: str        # robot name -> topic prefix (absolute)
    topics: Dict[str, str]          # role -> topic name relative to the prefix
    frame_format: str               # (robot name, frame) -> frame id
    range: RangeProfile
    imu_role: Optional[str]         # the role whose topic carries sensor_msgs/Imu (None: the
                                    # extras face publishes it, see extras below)
    odom_tf_from_odometry: bool     # odom -> base_link from wheel odometry (else ground truth)
    publishes_odometry: bool
    publishes_scan: bool
    has_gyro: bool                  # False: angular velocity 0, marked "no estimate" (REP 145)
    # The original's command semantics, the defaults of ~cmd_vel_scaling and ~cmd_timeout_s:
    # its own units, and commands that persist until the next one (0 = no watchdog).
    default_cmd_vel_scaling: str = "si"
    default_cmd_timeout_s: float = 0.0
    # frames of a robot at the root namespace: the prefix the original's single-robot launch
    # gives them (its default robot name)
    root_frame_prefix: str = "ePuck0"
    # what the driver publishes beyond the shared topics (ros/epuck/extras.py): roles among
    # imu, dist_sens, mag_field, battery, floor, microphone, motor_speed, rgb_leds
    extras: Tuple[str, ...] = ()
    microphones: int = 0             # microphone count of the `microphone` marker
    # the camera's default (width, height, mode "rgb" | "gray"): the drivers' cam_width,
    # cam_height, cam_mode defaults (a 160 x 2 grey slice); 40 x 40 colour for V-REP's model
    default_camera: Tuple[int, int, str] = (40, 40, "rgb")
    # odom's pose covariance diagonal (x, y, z, roll, pitch, yaw), None: zero
    odom_pose_variances: Optional[Tuple[float, ...]] = None

    def robot_name(self, index: int) -> str:
        return self.robot_name_format.format(index=index)

    def topic(self, robot_name: str, role: str) -> str:
        if robot_name == ROOT_NAMESPACE:
            return "/" + self.topics[role]
        return self.topic_prefix_format.format(robot=robot_name) + self.topics[role]

    def frame(self, robot_name: str, frame: str) -> str:
        return self.frame_format.format(robot=self.frame_prefix(robot_name), frame=frame)

    def frame_prefix(self, robot_name: str) -> str:
        return self.root_frame_prefix if robot_name == ROOT_NAMESPACE else robot_name


# both drivers' odom pose covariance: x, y 0.001; z, roll, pitch 1000 (not estimated); yaw 0.001
_DRIVER_ODOM_VARIANCES = (0.001, 0.001, 1000.0, 1000.0, 1000.0, 0.001)
_COMMON_TOPICS = {f"proximity{i}": f"proximity{i}" for i in range(PROXIMITY_COUNT)}

VREP = TopicProfile(
    name="vrep",
    robot_name_format="ePuck{index}",
    topic_prefix_format="/{robot}/",
    topics=dict(_COMMON_TOPICS, imu="imu", camera="camera", camera_info="camera_info",
                cmd_vel="cmd_vel", cmd_led="cmd_led", led_state="led_state",
                ground_truth="ground_truth"),
    frame_format="{robot}/{frame}",
    # field_of_view 30 degrees, min 1.5 mm, max = noDetectionDistance 5 cm (epuck_vrep_ros.lua)
    range=RangeProfile(field_of_view_rad=0.52359878, min_range_m=0.0015, max_range_m=0.05),
    imu_role="imu",
    odom_tf_from_odometry=False,
    publishes_odometry=False,
    publishes_scan=False,
    has_gyro=True,
    default_cmd_vel_scaling="vrep",     # epuck_vrep_ros.lua's formula; wheels keep their speed
)

EPUCK_DRIVER = TopicProfile(
    name="epuck_driver",
    robot_name_format="epuck_robot_{index}",
    topic_prefix_format="/{robot}/",
    topics=dict(_COMMON_TOPICS, imu="accel", camera="camera", camera_info="camera_info",
                cmd_vel="mobile_base/cmd_vel", cmd_led="mobile_base/cmd_led",
                led_state="led_state", odom="odom", scan="scan",
                ground_truth="ground_truth", floor="floor", microphone="microphone",
                motor_speed="motor_speed"),
    frame_format="{robot}/{frame}",
    # field_of_view 0.26, min 5 mm, max 5 cm (epuck_driver_cpp.cpp)
    range=RangeProfile(field_of_view_rad=0.26, min_range_m=0.005, max_range_m=0.05),
    imu_role="imu",
    odom_tf_from_odometry=True,
    publishes_odometry=True,
    publishes_scan=True,
    has_gyro=False,        # the e-puck 1's driver has an accelerometer only
    default_cmd_vel_scaling="epuck_driver",  # the driver's /3 and steps; the firmware keeps them
    root_frame_prefix="epuck_robot_0",       # epuck_controller.launch's default epuck_name
    extras=("floor", "microphone", "motor_speed"),
    microphones=3,
    default_camera=(160, 2, "gray"),
    odom_pose_variances=_DRIVER_ODOM_VARIANCES,
)

EPUCK2_DRIVER = TopicProfile(
    name="epuck2_driver",
    robot_name_format="epuck_robot_{index}",        # multi_epuck2.launch
    topic_prefix_format="/{robot}/",
    topics=dict(_COMMON_TOPICS, imu="imu", camera="camera", camera_info="camera_info",
                cmd_vel="mobile_base/cmd_vel", cmd_led="mobile_base/cmd_led",
                rgb_leds="mobile_base/rgb_leds", led_state="led_state", odom="odom",
                scan="scan", ground_truth="ground_truth", dist_sens="dist_sens",
                mag_field="mag_field", mag_field_vector="mag_field_vector", battery="battery",
                floor="floor", microphone="microphone"),
    frame_format="{robot}/{frame}",
    # field_of_view 0.26, min 5 mm, max 5 cm (epuck2_driver_cpp.cpp, as the e-puck 1's)
    range=RangeProfile(field_of_view_rad=0.26, min_range_m=0.005, max_range_m=0.05),
    imu_role=None,                  # Imu with roll/pitch from the accelerometer: extras.py
    odom_tf_from_odometry=True,
    publishes_odometry=True,
    publishes_scan=True,
    has_gyro=True,
    default_cmd_vel_scaling="epuck_driver",
    root_frame_prefix="epuck2_robot_0",      # epuck2_controller.launch's default epuck2_name
    extras=("imu", "dist_sens", "mag_field", "battery", "floor", "microphone", "rgb_leds"),
    microphones=4,
    default_camera=(160, 2, "gray"),
    odom_pose_variances=_DRIVER_ODOM_VARIANCES,
)

PROFILES: Dict[str, TopicProfile] = {p.name: p for p in (VREP, EPUCK_DRIVER, EPUCK2_DRIVER)}

# Child frames under <robot>/base_link, in the order V-REP's script sends them.
BASE_FRAME = "base_link"
PROX_FRAME_FORMAT = "base_prox{i}"
WHEEL_FRAMES: Tuple[str, str] = ("left_wheel", "right_wheel")
BODY_TOP_FRAME = "body_top"
CAMERA_FRAME = "camera_optical"      # REP 103 optical frame; V-REP used the literal "a"
LASER_FRAME = "base_laser"            # the driver profiles only
DIST_SENS_FRAME = "base_dist_sens"    # epuck2_driver only: the time-of-flight sensor
# epuck2_driver_cpp's TF base_dist_sens: (0.035, 0, 0.034), roll 0, pitch -0.21, yaw 0
DIST_SENS_MOUNT_M = (0.035, 0.0, 0.034)
DIST_SENS_PITCH_RAD = -0.21

# Driver's laser-scan emulation (epuck_driver_cpp): 19 beams from -90 to +90 degrees.
SCAN_BEAMS = 19
ROBOT_RADIUS_M = 0.035
