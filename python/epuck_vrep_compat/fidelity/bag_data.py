"""A robot's IR, IMU and cmd_vel series out of a bag (rosbag's API), as numpy arrays.

Times are seconds from the bag's first message of the robot (header stamps where the message
has them, else the bag's record time). The accelerometer is returned in REP 145's sign (+g on z
at rest): a bag in V-REP's sign (mean z < 0) is flipped, and ``vrep_sign`` says so.
"""
from dataclasses import dataclass, field

import numpy as np
import rosbag

from epuck_vrep_compat.fidelity.scenarios import RobotTopics, robot_topics, robots_in


class BagError(Exception):
    """A bag that cannot be used; the message says why."""


@dataclass
class Series:
    """The robot's recorded series."""

    robot: str
    ir: dict = field(default_factory=dict)    # k -> (t (N,), range (N,), max_range)
    imu_t: np.ndarray = None
    accel: np.ndarray = None                  # (N, 3) m/s², REP 145 sign
    gyro: np.ndarray = None                   # (N, 3) rad/s
    cmd_t: np.ndarray = None
    cmd_v: np.ndarray = None                  # commanded forward speed as recorded
    vrep_sign: bool = False
    duration_s: float = 0.0


def open_topics(path):
    """The topic names of a bag; BagError when it cannot be read."""
    try:
        with rosbag.Bag(path) as bag:
            return list(bag.get_type_and_topic_info().topics)
    except Exception as e:  # rosbag raises ROSBagException, OSError, ValueError, struct errors
        raise BagError(f"cannot read bag {path}: {e}") from e


def choose_robot(path, robot=None) -> RobotTopics:
    """The robot's topics (the first robot of the bag when ``robot`` is None)."""
    topics = open_topics(path)
    robots = robots_in(topics)
    if robot is None:
        if not robots:
            raise BagError(f"bag {path} holds no e-puck's proximity or IMU topics "
                           f"(has {sorted(topics)})")
        robot = robots[0]
    return robot_topics(topics, robot)


def read_series(path, topics: RobotTopics) -> Series:
    """Every message of the robot's topics, as arrays."""
    by_topic = {t: [] for t in list(topics.ir.values()) + [topics.imu, topics.cmd_vel] if t}
    try:
        with rosbag.Bag(path) as bag:
            for topic, msg, t in bag.read_messages(topics=list(by_topic)):
                header = getattr(msg, "header", None)
                stamp = header.stamp.to_sec() if header and not header.stamp.is_zero() \
                    else t.to_sec()
                by_topic[topic].append((stamp, msg))
    except Exception as e:
        raise BagError(f"cannot read bag {path}: {e}") from e
    starts = [m[0][0] for m in by_topic.values() if m]
    t0 = min(starts) if starts else 0.0
    s = Series(topics.robot)
    for k, topic in topics.ir.items():
        msgs = by_topic[topic]
        s.ir[k] = (np.array([t - t0 for t, _ in msgs]), np.array([m.range for _, m in msgs]),
                   float(msgs[0][1].max_range) if msgs else 0.05)
    if topics.imu:
        msgs = by_topic[topics.imu]
        s.imu_t = np.array([t - t0 for t, _ in msgs])
        s.accel = np.array([[m.linear_acceleration.x, m.linear_acceleration.y,
                             m.linear_acceleration.z] for _, m in msgs]).reshape(-1, 3)
        s.gyro = np.array([[m.angular_velocity.x, m.angular_velocity.y, m.angular_velocity.z]
                           for _, m in msgs]).reshape(-1, 3)
        if len(s.accel) and s.accel[:, 2].mean() < 0.0:
            s.accel, s.vrep_sign = -s.accel, True
    if topics.cmd_vel:
        msgs = by_topic[topics.cmd_vel]
        s.cmd_t = np.array([t - t0 for t, _ in msgs])
        s.cmd_v = np.array([m.linear.x for _, m in msgs])
    ends = [m[-1][0] - t0 for m in by_topic.values() if m]
    s.duration_s = max(ends) if ends else 0.0
    return s


def read_scenario_bag(path, robot, scenario) -> Series:
    """The robot's series for a scenario; BagError naming the scenario's topics the bag lacks."""
    topics = choose_robot(path, robot)
    missing = topics.missing(scenario)
    if missing:
        raise BagError(f"bag {path} lacks the {scenario.name} scenario's topics: "
                       + ", ".join(missing))
    return read_series(path, topics)
