"""IMU: specific force and angular rate in the body frame, with per-axis Gaussian noise."""
import math

import numpy as np

DT = 0.05


def test_at_rest_reads_gravity_up(make_swarm):
    swarm = make_swarm([(100, 0, 0, 1.0)])
    for _ in range(3):
        swarm.step(DT, np.zeros((1, 2)))
    assert np.array_equal(swarm.accel[0], [0.0, 0.0, 9.81])
    assert np.array_equal(swarm.gyro[0], [0.0, 0.0, 0.0])


def test_turning_reads_centripetal_acceleration_to_the_left(make_swarm):
    swarm = make_swarm()
    command = np.array([[2.0, 4.0]])
    for _ in range(50):
        swarm.step(DT, command)
    v, w = 0.02 * 3.0, 0.02 * 2.0 / 0.053
    # Velocities are step chords, of length v dt sinc(w dt / 2); successive chords turn by
    # w dt, so |Δv| / dt = 2 |chord| sin(w dt / 2) / dt^2, pointing to the centre (body +y).
    half_turn = w * DT / 2
    chord_speed = v * math.sin(half_turn) / half_turn
    centripetal = 2 * chord_speed * math.sin(half_turn) / DT
    assert np.allclose(swarm.accel[0], [0, centripetal, 9.81], atol=1e-9)
    assert np.allclose(swarm.gyro[0], [0, 0, w])


def test_first_step_and_teleport_read_no_acceleration(make_swarm):
    swarm = make_swarm()
    swarm.step(DT, np.array([[5.0, 5.0]]))
    assert np.array_equal(swarm.accel[0], [0, 0, 9.81])
    swarm.set_pose(0, 1.0, 1.0, 0.0)
    swarm.step(DT, np.array([[5.0, 5.0]]))
    assert np.array_equal(swarm.accel[0], [0, 0, 9.81])


def test_noise_standard_deviation(make_swarm):
    swarm = make_swarm()
    accel_sd, gyro_sd = np.array([0.1, 0.2, 0.3]), np.array([0.01, 0.02, 0.03])
    swarm.set_imu_noise(accel_sd[None, :], gyro_sd[None, :])
    samples = 4000
    accel, gyro = np.empty((samples, 3)), np.empty((samples, 3))
    for i in range(samples):
        swarm.step(DT, np.zeros((1, 2)))
        accel[i], gyro[i] = swarm.accel[0], swarm.gyro[0]
    standard_error = 3 / math.sqrt(2 * (samples - 1))
    assert np.all(np.abs(accel.std(axis=0, ddof=1) / accel_sd - 1) < standard_error)
    assert np.all(np.abs(gyro.std(axis=0, ddof=1) / gyro_sd - 1) < standard_error)
    assert np.all(np.abs(accel.mean(axis=0) - [0, 0, 9.81]) < 3 * accel_sd / math.sqrt(samples))
