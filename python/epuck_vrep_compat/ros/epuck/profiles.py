"""The e-puck topic profiles: what each face of a simulated e-puck publishes and how, on the
profile's names (:mod:`epuck_vrep_compat.compat.epuck_names`, where the three profiles are
described): fixed fields of its Range messages, which topics it has, its command semantics'
defaults, its extra sensors, camera and covariances."""
from dataclasses import dataclass, fields
from typing import Dict, Optional, Tuple

from epuck_vrep_compat.compat import epuck_names
from epuck_vrep_compat.compat.cmd_vel import PROFILE_SCALINGS
from epuck_vrep_compat.compat.epuck_names import ProfileNames


@dataclass(frozen=True)
class RangeProfile:
    """Fixed fields of the ``sensor_msgs/Range`` messages a profile publishes."""

    field_of_view_rad: float
    min_range_m: float
    max_range_m: float


@dataclass(frozen=True, kw_only=True)
class TopicProfile(ProfileNames):
    """Names and message conventions of one face of a simulated e-puck."""

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
    # what the driver publishes beyond the shared topics (ros/epuck/drivers/extras.py): roles
    # among imu, dist_sens, mag_field, battery, floor, microphone, motor_speed, rgb_leds
    extras: Tuple[str, ...] = ()
    microphones: int = 0             # microphone count of the `microphone` marker
    # the camera's default (width, height, mode "rgb" | "gray"): the drivers' cam_width,
    # cam_height, cam_mode defaults (a 160 x 2 grey slice); 40 x 40 colour for V-REP's model
    default_camera: Tuple[int, int, str] = (40, 40, "rgb")
    # odom's pose covariance diagonal (x, y, z, roll, pitch, yaw), None: zero
    odom_pose_variances: Optional[Tuple[float, ...]] = None

    @classmethod
    def on(cls, names: ProfileNames, **conventions) -> "TopicProfile":
        """The profile of these names, with these conventions."""
        return cls(**{f.name: getattr(names, f.name) for f in fields(ProfileNames)},
                   **conventions)


# both drivers' odom pose covariance: x, y 0.001; z, roll, pitch 1000 (not estimated); yaw 0.001
_DRIVER_ODOM_VARIANCES = (0.001, 0.001, 1000.0, 1000.0, 1000.0, 0.001)

VREP = TopicProfile.on(
    epuck_names.VREP,
    # field_of_view 30 degrees, min 1.5 mm, max = noDetectionDistance 5 cm (epuck_vrep_ros.lua)
    range=RangeProfile(field_of_view_rad=0.52359878, min_range_m=0.0015, max_range_m=0.05),
    imu_role="imu",
    odom_tf_from_odometry=False,
    publishes_odometry=False,
    publishes_scan=False,
    has_gyro=True,
    default_cmd_vel_scaling=PROFILE_SCALINGS["vrep"],   # epuck_vrep_ros.lua's formula
)

EPUCK_DRIVER = TopicProfile.on(
    epuck_names.EPUCK_DRIVER,
    # field_of_view 0.26, min 5 mm, max 5 cm (epuck_driver_cpp.cpp)
    range=RangeProfile(field_of_view_rad=0.26, min_range_m=0.005, max_range_m=0.05),
    imu_role="imu",
    odom_tf_from_odometry=True,
    publishes_odometry=True,
    publishes_scan=True,
    has_gyro=False,        # the e-puck 1's driver has an accelerometer only
    default_cmd_vel_scaling=PROFILE_SCALINGS["epuck_driver"],  # the driver's /3 and steps
    extras=("floor", "microphone", "motor_speed"),
    microphones=3,
    default_camera=(160, 2, "gray"),
    odom_pose_variances=_DRIVER_ODOM_VARIANCES,
)

EPUCK2_DRIVER = TopicProfile.on(
    epuck_names.EPUCK2_DRIVER,
    # field_of_view 0.26, min 5 mm, max 5 cm (epuck2_driver_cpp.cpp, as the e-puck 1's)
    range=RangeProfile(field_of_view_rad=0.26, min_range_m=0.005, max_range_m=0.05),
    imu_role=None,                  # Imu with roll/pitch from the accelerometer: extras.py
    odom_tf_from_odometry=True,
    publishes_odometry=True,
    publishes_scan=True,
    has_gyro=True,
    default_cmd_vel_scaling=PROFILE_SCALINGS["epuck2_driver"],
    extras=("imu", "dist_sens", "mag_field", "battery", "floor", "microphone", "rgb_leds"),
    microphones=4,
    default_camera=(160, 2, "gray"),
    odom_pose_variances=_DRIVER_ODOM_VARIANCES,
)

PROFILES: Dict[str, TopicProfile] = {p.name: p for p in (VREP, EPUCK_DRIVER, EPUCK2_DRIVER)}

# epuck2_driver_cpp's TF base_dist_sens: (0.035, 0, 0.034), roll 0, pitch -0.21, yaw 0
DIST_SENS_MOUNT_M = (0.035, 0.0, 0.034)
DIST_SENS_PITCH_RAD = -0.21

# Driver's laser-scan emulation (epuck_driver_cpp): 19 beams from -90 to +90 degrees.
SCAN_BEAMS = 19
ROBOT_RADIUS_M = 0.035
