"""fit_noise recovers known, non-default noise parameters from bags made by the simulator's core
(within 3 standard errors, which it writes), and refuses unusable bags with exit status 1."""
import math

import numpy as np
import pytest
import rosbag
import rospy
import yaml
from geometry_msgs.msg import Twist
from sensor_msgs.msg import Imu, Range

from epuck_vrep_compat import CollisionWorld, EpuckModel, EpuckSwarm
from epuck_vrep_compat.fidelity.fit_noise import main
from epuck_vrep_compat.fidelity.scenarios import SCENARIOS, robot_topics, robots_in
from epuck_vrep_compat.epuck.noise import IrNoise, NoiseSettings

STEP_S = 0.05
TRUE = NoiseSettings(
    ir=IrNoise(probability=np.linspace(0.05, 0.40, 8), mean_m=np.full(8, 0.010),
               stddev_m=np.linspace(0.001, 0.003, 8)),
    accel_stddev_m_s2=np.array([0.02, 0.045, 0.07]),
    accel_bias_m_s2=np.array([0.12, -0.3, 0.2]),
    gyro_stddev_rad_s=np.array([0.002, 0.004, 0.01]),
    gyro_bias_rad_s=np.array([0.0, 0.01, -0.02]), wheel_slip_stddev=0.03)


def make_bag(path, robot, imu_name, speed_m_s, steps, sign=1.0, cmd_topic="cmd_vel"):
    """The core's readings of one robot in open space, as the profile's messages (``robot``
    "/": at the root namespace)."""
    prefix = "/" if robot == "/" else f"/{robot}/"
    swarm = EpuckSwarm(CollisionWorld(), EpuckModel(), 11)
    swarm.add_robot(10, 0.0, 0.0, 0.0)
    TRUE.apply(swarm, [robot])
    with rosbag.Bag(path, "w") as bag:
        for i in range(steps):
            v = speed_m_s if i >= 20 else 0.0
            swarm.step(STEP_S, np.full((1, 2), v / 0.02))
            stamp = rospy.Time.from_sec((i + 1) * STEP_S)
            cmd = Twist()
            cmd.linear.x = v
            bag.write(f"{prefix}{cmd_topic}", cmd, stamp)
            imu = Imu()
            imu.header.stamp = stamp
            a, g = swarm.accel[0] * sign, swarm.gyro[0]
            imu.linear_acceleration.x, imu.linear_acceleration.y, imu.linear_acceleration.z = a
            imu.angular_velocity.x, imu.angular_velocity.y, imu.angular_velocity.z = g
            bag.write(f"{prefix}{imu_name}", imu, stamp)
            for k in range(8):
                r = Range(range=swarm.ranges[0, k], min_range=0.0015, max_range=0.05)
                r.header.stamp = stamp
                bag.write(f"{prefix}proximity{k}", r, stamp)


def within_3_se(estimates, truth):
    for est, true in zip(estimates, truth):
        assert abs(est["value"] - true) < 3 * est["se"], (est, true)


def test_rest_recovers_ir_and_imu_parameters(tmp_path):
    bag, out = str(tmp_path / "rest.bag"), str(tmp_path / "rest_noise.yaml")
    make_bag(bag, "ePuck0", "imu", 0.0, 5000)
    assert main([bag, "--scenario", "rest", "-o", out]) == 0
    data = yaml.safe_load(open(out))
    fit = data["fit"]
    for k in range(8):
        f = fit["ir"][f"proximity{k}"]
        assert f["samples"] == 5000 and f["errors"] > 100
        within_3_se([f["probability"], f["mean_m"], f["stddev_m"]],
                    [TRUE.ir.probability[k], TRUE.ir.mean_m[k], TRUE.ir.stddev_m[k]])
        p = f["probability"]
        assert p["ci95"] == pytest.approx([p["value"] - 1.96 * p["se"], p["value"] + 1.96 * p["se"]])
    within_3_se(fit["accel"]["bias"], TRUE.accel_bias_m_s2)
    within_3_se(fit["accel"]["stddev"], TRUE.accel_stddev_m_s2)
    within_3_se(fit["gyro"]["bias"], TRUE.gyro_bias_rad_s)
    within_3_se(fit["gyro"]["stddev"], TRUE.gyro_stddev_rad_s)
    assert fit["accel"]["samples"] == 5000
    assert data["imu_noise"]["accel_bias_m_s2"] == [b["value"] for b in fit["accel"]["bias"]]


def test_straight_in_driver_names_and_vrep_sign_recovers_the_sensors_own_noise(tmp_path):
    bag, out = str(tmp_path / "straight.bag"), str(tmp_path / "s.yaml")
    make_bag(bag, "epuck_robot_0", "accel", 0.04, 5000, sign=-1.0,
             cmd_topic="mobile_base/cmd_vel")
    assert main([bag, "--scenario", "straight", "-o", out, "--wheel-slip", "0.03"]) == 0
    data = yaml.safe_load(open(out))
    assert data["fit"]["accel_sign"] == "vrep" and data["fit"]["robot"] == "epuck_robot_0"
    within_3_se(data["fit"]["accel"]["bias"], TRUE.accel_bias_m_s2)
    sd = data["imu_noise"]["accel_stddev_m_s2"]
    se = [s["se"] for s in data["fit"]["accel"]["stddev"]]
    # x: the measured total (0.036) less slip's 0.03 m/s² gives back the sensor's 0.02.
    for axis in range(3):
        assert abs(sd[axis] - TRUE.accel_stddev_m_s2[axis]) < 3 * se[axis] * (
            2.0 if axis == 0 else 1.0), (axis, sd)


def test_bag_without_the_scenarios_topics_exits_1_naming_them(tmp_path, capsys):
    bag = str(tmp_path / "imu_only.bag")
    with rosbag.Bag(bag, "w") as b:
        b.write("/ePuck0/imu", Imu(), rospy.Time(1))
    assert main([bag, "--scenario", "wall"]) == 1
    err = capsys.readouterr().err
    for k in (0, 1, 6, 7):
        assert f"/ePuck0/proximity{k}" in err
    assert main([bag, "--scenario", "rest"]) == 1
    assert "/ePuck0/proximity3" in capsys.readouterr().err


@pytest.mark.parametrize("content", [b"", b"not a bag at all" * 100])
def test_unreadable_bag_exits_1(tmp_path, capsys, content):
    bag = tmp_path / "broken.bag"
    bag.write_bytes(content)
    assert main([str(bag), "--scenario", "rest"]) == 1
    assert "cannot read bag" in capsys.readouterr().err
    assert main([str(tmp_path / "missing.bag"), "--scenario", "rest"]) == 1


def test_wall_fits_the_wall_sensors_after_the_reversal_and_pools_the_others(tmp_path):
    bag, out = str(tmp_path / "wall.bag"), str(tmp_path / "w.yaml")
    make_bag(bag, "ePuck0", "imu", 0.0, 200)          # no reversal recorded: 3 s assumed
    assert main([bag, "--scenario", "wall", "-o", out]) == 0
    data = yaml.safe_load(open(out))
    assert sorted(data["fit"]["ir"]) == [f"proximity{k}" for k in (0, 1, 6, 7)]
    # from 1 s after the 3 s drive: relative stamps 4.0 .. 9.95 s (the first may round below)
    assert data["fit"]["ir"]["proximity0"]["samples"] in (119, 120)
    assert "imu_noise" not in data and "accel" not in data["fit"]
    p = data["ir_noise"]["probability"]
    assert p[2] == p[3] == p[4] == p[5] == pytest.approx(np.mean([p[0], p[1], p[6], p[7]]))


def test_robots_are_found_at_the_root_and_in_nested_namespaces():
    """The names the launch files take (names:=/ puts one robot at the root namespace, as the
    drivers' launch files do; namespaces may be nested) are the names fit_noise finds."""
    topics = [f"/proximity{k}" for k in range(8)] + ["/imu", "/cmd_vel", "/tf", "/clock"]
    topics += [f"/team_a/epuck_1/proximity{k}" for k in range(8)] + ["/team_a/epuck_1/accel"]
    topics += ["/ePuck0/imu", "/team_a/epuck_1/mobile_base/cmd_vel"]
    assert robots_in(topics) == ["/", "ePuck0", "team_a/epuck_1"]
    root = robot_topics(topics, "/")
    assert root.ir == {k: f"/proximity{k}" for k in range(8)}
    assert (root.imu, root.cmd_vel) == ("/imu", "/cmd_vel")
    nested = robot_topics(topics, "/team_a/epuck_1/")      # slashes around a name are ignored
    assert nested.robot == "team_a/epuck_1" and nested.ir[7] == "/team_a/epuck_1/proximity7"
    assert (nested.imu, nested.cmd_vel) == ("/team_a/epuck_1/accel",
                                            "/team_a/epuck_1/mobile_base/cmd_vel")
    only_imu = robot_topics(topics, "ePuck0")
    assert only_imu.missing(SCENARIOS["rest"])[0] == "/ePuck0/proximity0"
    assert robot_topics(["/imu"], "/").missing(SCENARIOS["wall"])[0] == "/proximity0"


def test_a_robot_at_the_root_namespace_is_fitted(tmp_path):
    bag, out = str(tmp_path / "root.bag"), str(tmp_path / "root_noise.yaml")
    make_bag(bag, "/", "imu", 0.0, 2000)
    assert main([bag, "--scenario", "rest", "-o", out]) == 0
    data = yaml.safe_load(open(out))
    assert data["fit"]["robot"] == "/"
    assert data["fit"]["ir"]["proximity0"]["samples"] == 2000
    assert data["fit"]["accel"]["samples"] == 2000
    assert main([bag, "--scenario", "rest", "-o", out, "--robot", "/"]) == 0
