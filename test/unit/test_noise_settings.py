"""Noise configuration: validation names the option; per-robot, per-sensor values reach the
core; the master switch turns every source off."""
import numpy as np
import pytest

from epuck_vrep_compat import CollisionWorld, EpuckModel, EpuckSwarm
from epuck_vrep_compat.epuck.noise import (IrNoise, NoiseConfigError, NoiseSettings, per_sensor,
                                          triple)


def _swarm(n):
    swarm = EpuckSwarm(CollisionWorld(), EpuckModel(), 7)
    for i in range(n):
        swarm.add_robot(10 + i, 0.5 * i, 0.0, 0.0)
    return swarm


def test_per_sensor_accepts_scalar_or_eight_and_names_the_option():
    np.testing.assert_array_equal(per_sensor(0.2, "p"), np.full(8, 0.2))
    np.testing.assert_array_equal(per_sensor(list(range(8)), "p"), np.arange(8.0))
    for bad in ([1, 2, 3], "x", [0.1] * 7 + [float("nan")], True):
        with pytest.raises(NoiseConfigError, match="option 'p' must be"):
            per_sensor(bad, "p")
    with pytest.raises(NoiseConfigError, match="option 'ir_noise/stddev_m' must be >= 0.0"):
        per_sensor(-0.1, "ir_noise/stddev_m", 0.0)
    with pytest.raises(NoiseConfigError, match="option 'probability' must be <= 1.0"):
        per_sensor(1.5, "probability", 0.0, 1.0)
    with pytest.raises(NoiseConfigError, match="option 'a' must be >= 0.0"):
        triple([-1, 0, 0], "a")


def test_messages_name_the_option_and_speak_no_ros(tmp_path):
    """The noise layer is ROS-free: its messages name the option plainly (``option
    'noise_preset'``), never a private parameter; the node words its own from option and
    problem."""
    from epuck_vrep_compat.epuck.noise_presets import load_noise_file, preset
    path = tmp_path / "noise.yaml"
    path.write_text("ir_noise: {stddev_m: -1}\n")
    calls = (lambda: preset("real"), lambda: per_sensor(-1, "ir_noise/mean_m", 0.0),
             lambda: load_noise_file(str(path), preset("real_robot")),
             lambda: load_noise_file(str(tmp_path / "missing.yaml"), preset("real_robot")))
    for call in calls:
        with pytest.raises(NoiseConfigError) as caught:
            call()
        e = caught.value
        assert str(e) == f"option '{e.option}' {e.problem}"
        assert "~" not in str(e) and "parameter" not in str(e), str(e)
    with pytest.raises(NoiseConfigError) as caught:
        load_noise_file(str(path), preset("real_robot"))
    assert caught.value.option == "noise_file"
    assert caught.value.problem == f"({path}): 'ir_noise/stddev_m' must be >= 0.0, got " \
                                   f"{[-1.0] * 8}"


def test_per_robot_override_changes_only_that_robot():
    # Readings at max range: with probability 1 and a large SD every reading of robot 1 moves
    # inward, robot 0 keeps the default (probability 0 here) and reads exactly max range.
    settings = NoiseSettings(ir=IrNoise(probability=np.zeros(8), mean_m=np.zeros(8),
                                        stddev_m=np.zeros(8)),
                             accel_stddev_m_s2=np.zeros(3), gyro_stddev_rad_s=np.zeros(3),
                             wheel_slip_stddev=0.0)
    settings.ir_per_robot["ePuck1"] = IrNoise(probability=np.ones(8), mean_m=np.full(8, 0.01),
                                       stddev_m=np.full(8, 0.001))
    swarm = _swarm(2)
    settings.apply(swarm, ["ePuck0", "ePuck1"])
    swarm.step(0.05, np.zeros((2, 2)))
    np.testing.assert_array_equal(swarm.ranges[0], swarm.ranges_clean[0])
    assert np.all(swarm.ranges[1] < swarm.ranges_clean[1])


def test_master_switch_turns_every_source_off():
    swarm = _swarm(1)
    NoiseSettings(enabled=False).apply(swarm, ["ePuck0"])
    for _ in range(5):
        swarm.step(0.05, np.array([[1.0, 1.0]]))
    np.testing.assert_array_equal(swarm.ranges, swarm.ranges_clean)
    np.testing.assert_allclose(swarm.poses[0, :2], swarm.odometry[0, :2], atol=1e-12)


def test_presets_and_the_noise_file(tmp_path):
    from epuck_vrep_compat.epuck.noise_presets import load_noise_file, preset
    with pytest.raises(NoiseConfigError, match="option 'noise_preset' must be one of"):
        preset("real")
    path = tmp_path / "noise.yaml"
    path.write_text("ir_noise: {probability: 0.3}\n"
                    "imu_noise: {accel_bias_m_s2: [0.1, -0.2, 0.0]}\nfit: {anything: 1}\n")
    s = load_noise_file(str(path), preset("vrep"))
    np.testing.assert_array_equal(s.ir.probability, np.full(8, 0.3))
    np.testing.assert_array_equal(s.ir.stddev_m, np.zeros(8))               # the preset's
    np.testing.assert_array_equal(s.accel_bias_m_s2, [0.1, -0.2, 0.0])
    for text, name in (("imu_noise: {accel_stddev_m_s2: -1}", "accel_stddev_m_s2"),
                       ("ir_noise: {probabilty: 0.1}", "ir_noise"),
                       ("wheel_slip: 0.1", "noise file"), ("[1, 2", "cannot read")):
        path.write_text(text)
        with pytest.raises(NoiseConfigError, match=name):
            load_noise_file(str(path), preset("real_robot"))
    with pytest.raises(NoiseConfigError, match="cannot read"):
        load_noise_file(str(tmp_path / "missing.yaml"), preset("real_robot"))


def test_imu_bias_reaches_the_core_and_bad_bias_is_refused():
    swarm = _swarm(1)
    NoiseSettings(accel_stddev_m_s2=np.zeros(3), gyro_stddev_rad_s=np.zeros(3),
                  accel_bias_m_s2=np.array([0.1, -0.2, 0.3]),
                  gyro_bias_rad_s=np.array([0.0, 0.0, 0.01])).apply(swarm, ["ePuck0"])
    for _ in range(3):
        swarm.step(0.05, np.zeros((1, 2)))
    np.testing.assert_allclose(swarm.accel[0], [0.1, -0.2, 9.81 + 0.3], atol=1e-12)
    np.testing.assert_allclose(swarm.gyro[0], [0.0, 0.0, 0.01], atol=1e-12)
    for bad in (np.full((1, 3), np.nan), np.full((1, 3), 1e4), np.zeros((2, 3))):
        with pytest.raises(ValueError):
            swarm.set_imu_bias(bad, np.zeros((1, 3)))
