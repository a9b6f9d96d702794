"""policy_node's logic without a master: the policy's command for one IR cycle in each cmd_vel
scaling, the IMU, neighbour and camera blocks from messages, loading ``pkg.module:function``."""
import math

import numpy as np
import pytest
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Image, Imu

from epuck_vrep_compat.compat.cmd_vel import MAX_WHEEL_SPEED_RAD_S, wheel_speeds
from epuck_vrep_compat.nodes.policy_node import PolicyRunner, load_function
from epuck_vrep_compat.policy.observation import ObservationLayout, camera_row
from epuck_vrep_compat.ros.common.params import ParamError

RANGES = [0.05, 0.03, 0.05, 0.05, 0.05, 0.05, 0.05, 0.01]


@pytest.mark.parametrize("scaling", ["si", "vrep", "epuck_driver"])
def test_the_twist_gives_the_policys_wheel_speeds(scaling):
    runner = PolicyRunner(lambda obs: (0.5, -0.25), ObservationLayout(), scaling, "ePuck0")
    v, w = runner.control(RANGES, [0.05] * 8)
    left, right = wheel_speeds(scaling, v, w)
    step = 2 * math.pi / 1000 if scaling == "epuck_driver" else 1e-9
    assert (left, right) == pytest.approx((0.5 * MAX_WHEEL_SPEED_RAD_S,
                                           -0.25 * MAX_WHEEL_SPEED_RAD_S), abs=step)
    assert runner.last_observation[7] == pytest.approx(0.04 / 0.045)


def odometry(x, y, yaw):
    msg = Odometry()
    msg.pose.pose.position.x, msg.pose.pose.position.y = x, y
    msg.pose.pose.orientation.z, msg.pose.pose.orientation.w = math.sin(yaw / 2), math.cos(yaw / 2)
    return msg


def test_imu_and_neighbours_come_from_the_messages():
    layout = ObservationLayout(imu=True, neighbours=2, neighbour_range_m=0.5)
    runner = PolicyRunner(lambda obs: (0.0, 0.0), layout, "si", "ePuck0")
    imu = Imu()
    imu.linear_acceleration.z, imu.angular_velocity.z = 9.81, 1.0
    runner.on_imu(imu)
    runner.on_pose(odometry(0.0, 0.0, math.pi / 2), "ePuck0")
    runner.on_pose(odometry(0.2, 0.0, 0.0), "ePuck1")
    obs = runner.observe(RANGES)
    assert obs[8:14] == pytest.approx([0, 0, 1.0, 0, 0, 0.2])
    assert obs[14:17] == pytest.approx([0.6, 0.0, -1.0], abs=1e-12)   # on its right
    assert obs[17:].tolist() == [0.0, 0.0, 0.0]


def image(width, height, encoding, pixels):
    msg = Image(width=width, height=height, encoding=encoding)
    msg.step = width * (3 if encoding == "rgb8" else 1)
    msg.data = np.asarray(pixels, np.uint8).tobytes()
    return msg


def test_camera_block_from_the_camera_topic_zeros_until_the_first_image():
    layout = ObservationLayout(camera=True, camera_bins=4)
    runner = PolicyRunner(lambda obs: (0.0, 0.0), layout, "si", "epuck_robot_0")
    assert runner.observe(RANGES)[8:].tolist() == [0.0] * 4
    rgb = np.random.default_rng(3).integers(0, 256, (40, 40, 3), dtype=np.uint8)
    runner.on_camera(image(40, 40, "rgb8", rgb))
    assert np.array_equal(runner.observe(RANGES)[8:], camera_row(rgb, 4))
    mono = np.arange(320).reshape(2, 160) % 256
    runner.on_camera(image(160, 2, "mono8", mono))
    assert np.array_equal(runner.observe(RANGES)[8:], camera_row(mono.astype(np.uint8), 4))
    runner.on_camera(image(4, 1, "bgr8", np.zeros(12)))       # ignored, with a warning
    assert np.array_equal(runner.observe(RANGES)[8:], camera_row(mono.astype(np.uint8), 4))


def test_load_function_names_the_parameter():
    assert load_function("numpy:tanh") is np.tanh
    for bad in ("numpy.tanh", "no_such_module_xyz:f", "numpy:no_such_function"):
        with pytest.raises(ParamError, match="~policy"):
            load_function(bad)
