"""Every compatibility name of the e-puck topic profiles, defined once: robots, topics, frames.

Profile ``vrep`` reproduces the V-REP e-puck model (andrei91ro/epuck_vrep_ros.lua): absolute
topics ``/ePuckK/...``, frames ``ePuckK/...`` under a shared ``odom``.
Profile ``epuck_driver`` reproduces the real robot's driver (gctronic/epuck_driver_cpp, the
``multi_epuck.launch`` layout): namespace ``epuck_robot_K``, commands under ``mobile_base/``.
Profile ``epuck2_driver`` reproduces the e-puck2's (the same repository, branch ``e-puck2``,
``epuck2_driver_cpp.cpp`` and ``multi_epuck2.launch``): the same layout, an ``imu``, the
time-of-flight sensor, magnetometer, battery, ground sensors, microphones and RGB LEDs.

What each profile publishes and how (message fields, defaults) is the e-puck face's:
:mod:`epuck_vrep_compat.ros.epuck.profiles` builds its profiles on these names.
"""
from dataclasses import dataclass
from typing import Dict, Tuple

PROXIMITY_COUNT = 8
ROOT_NAMESPACE = "/"     # a robot name: its topics at the root, as a driver's single-robot launch


@dataclass(frozen=True)
class ProfileNames:
    """The names one topic profile gives a simulated e-puck: robots, topics, frames."""

    name: str
    robot_name_format: str          # robot index -> robot name
    topic_prefix_format: str        # robot name -> topic prefix (absolute)
    topics: Dict[str, str]          # role -> topic name relative to the prefix
    frame_format: str               # (robot name, frame) -> frame id
    # frames of a robot at the root namespace: the prefix the original's single-robot launch
    # gives them (its default robot name)
    root_frame_prefix: str = "ePuck0"

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


_COMMON_TOPICS = {f"proximity{i}": f"proximity{i}" for i in range(PROXIMITY_COUNT)}

VREP = ProfileNames(
    name="vrep",
    robot_name_format="ePuck{index}",
    topic_prefix_format="/{robot}/",
    topics=dict(_COMMON_TOPICS, imu="imu", camera="camera", camera_info="camera_info",
                cmd_vel="cmd_vel", cmd_led="cmd_led", led_state="led_state",
                ground_truth="ground_truth"),
    frame_format="{robot}/{frame}",
)

EPUCK_DRIVER = ProfileNames(
    name="epuck_driver",
    robot_name_format="epuck_robot_{index}",
    topic_prefix_format="/{robot}/",
    topics=dict(_COMMON_TOPICS, imu="accel", camera="camera", camera_info="camera_info",
                cmd_vel="mobile_base/cmd_vel", cmd_led="mobile_base/cmd_led",
                led_state="led_state", odom="odom", scan="scan",
                ground_truth="ground_truth", floor="floor", microphone="microphone",
                motor_speed="motor_speed"),
    frame_format="{robot}/{frame}",
    root_frame_prefix="epuck_robot_0",       # epuck_controller.launch's default epuck_name
)

EPUCK2_DRIVER = ProfileNames(
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
    root_frame_prefix="epuck2_robot_0",      # epuck2_controller.launch's default epuck2_name
)

PROFILE_NAMES: Dict[str, ProfileNames] = {p.name: p for p in (VREP, EPUCK_DRIVER, EPUCK2_DRIVER)}

# V-REP's e-puck model: its root object's name and its parts' (a copy's carry V-REP's "#k").
MODEL_ROOT_OBJECT = "ePuck"


def model_object_name(part: str) -> str:
    """The V-REP name of a part of the e-puck model (``leftJoint``: ``ePuck_leftJoint``); the
    proximity sensors' dummies have no prefix (``dummy_proxSensor0``)."""
    return part if part.startswith("dummy_") else f"{MODEL_ROOT_OBJECT}_{part}"


# Child frames under <robot>/base_link, in the order V-REP's script sends them.
BASE_FRAME = "base_link"
PROX_FRAME_FORMAT = "base_prox{i}"
WHEEL_FRAMES: Tuple[str, str] = ("left_wheel", "right_wheel")
BODY_TOP_FRAME = "body_top"
CAMERA_FRAME = "camera_optical"      # REP 103 optical frame; V-REP used the literal "a"
LASER_FRAME = "base_laser"            # the driver profiles only
DIST_SENS_FRAME = "base_dist_sens"    # epuck2_driver only: the time-of-flight sensor
