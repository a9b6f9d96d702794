"""The policy package (observation builder, neighbours, perceptron and its weights file) and the
cmd_vel scalings both ways: pure logic, no ROS, no core."""
import json
import math

import numpy as np
import pytest

from epuck_vrep_compat.compat import cmd_vel
from epuck_vrep_compat.policy import neighbours as nb
from epuck_vrep_compat.policy import observation as ob
from epuck_vrep_compat.policy.controller import FORMAT, Perceptron, braitenberg

RNG = np.random.default_rng(25)


def test_ir_activation_is_the_same_for_every_profiles_clipped_range():
    """A reading of the core in metres and the same reading clipped to any profile's Range
    limits (vrep 1.5 mm, drivers 5 mm, both 5 cm) give one activation."""
    raw = np.array([0.0, 0.001, 0.004, 0.005, 0.0275, 0.049, 0.05, 0.05])
    expected = np.array([1.0, 1.0, 1.0, 1.0, 0.5, 1.0 / 45.0, 0.0, 0.0])
    assert ob.ir_activation(raw) == pytest.approx(expected, abs=1e-12)
    for low in (0.0015, 0.005):
        assert ob.ir_activation(np.clip(raw, low, 0.05)) == pytest.approx(expected, abs=1e-12)
    assert ob.ir_activation([math.inf, math.nan] + [0.05] * 6)[:2].tolist() == [0.0, 0.0]


def test_layout_names_size_and_bounds():
    layout = ob.ObservationLayout(imu=True, neighbours=2, neighbour_range_m=0.4)
    assert layout.size == 8 + 6 + 6 == len(layout.names)
    assert layout.names[8:14] == list(ob.IMU_NAMES)
    assert layout.names[14:] == ["nb0_near", "nb0_cos", "nb0_sin", "nb1_near", "nb1_cos",
                                 "nb1_sin"]
    low, high = layout.bounds()
    assert low[8] == -4.0 and high[8] == 4.0 and low[14] == 0.0 and low[15] == -1.0
    assert ob.ObservationLayout.from_dict(layout.to_dict()) == layout
    with pytest.raises(ValueError):
        ob.ObservationLayout.from_dict(dict(layout.to_dict(), names=["ir0"]))
    with pytest.raises(ValueError):
        ob.ObservationLayout(neighbours=-1)


def test_build_scales_the_imu_and_batches():
    layout = ob.ObservationLayout(imu=True)
    ranges = RNG.uniform(0.0, 0.06, (5, 8))
    accel = np.tile([0.0, 0.0, 9.81], (5, 1))
    gyro = np.tile([0.0, 0.0, 2.5], (5, 1))
    obs = ob.build(layout, ranges, accel, gyro)
    assert obs.shape == (5, 14)
    assert obs[:, 8:11] == pytest.approx(np.tile([0.0, 0.0, 1.0], (5, 1)))
    assert obs[:, 13] == pytest.approx(0.5)
    assert obs[2] == pytest.approx(ob.build(layout, ranges[2], accel[2], gyro[2]))
    assert ob.build(layout, ranges[0], [0, 0, 1e3], [0, 0, 0])[10] == 4.0
    with pytest.raises(ValueError):
        ob.build(layout, ranges)


def test_neighbours_block_nearest_first_in_the_robots_frame():
    own = (1.0, 1.0, math.pi / 2)                 # facing +y
    others = [(1.0, 1.3), (0.8, 1.0), (5.0, 5.0)]   # ahead 0.3, to the right 0.2, out of range
    block = nb.block(own, others, 3, 0.5)
    assert block[:3] == pytest.approx([1 - 0.2 / 0.5, math.cos(math.pi / 2),
                                       math.sin(math.pi / 2)])    # on its left (x smaller)
    assert block[3:6] == pytest.approx([1 - 0.3 / 0.5, 1.0, 0.0])
    assert block[6:].tolist() == [0.0, 0.0, 0.0]
    poses = np.array([[0, 0, 0], [0.1, 0, 0], [3, 3, 0], [3.2, 3, 0]], float)
    blocks = nb.blocks(poses, 1, 0.5, groups=2)     # two worlds of two robots
    assert blocks[0] == pytest.approx([0.8, 1.0, 0.0])
    assert blocks[3] == pytest.approx([0.6, -1.0, 0.0], abs=1e-12)


def test_perceptron_flat_round_trip_and_file(tmp_path):
    layout = ob.ObservationLayout(imu=True)
    flat = RNG.normal(size=Perceptron.parameter_count(layout))
    p = Perceptron.from_flat(flat, layout, {"task": "test"})
    assert p.flat() == pytest.approx(flat)
    obs = RNG.uniform(size=(3, layout.size))
    assert p(obs) == pytest.approx(np.tanh(obs @ flat[:-2].reshape(2, -1).T + flat[-2:]))
    path = tmp_path / "w.json"
    p.save(str(path))
    data = json.loads(path.read_text())
    assert data["format"] == FORMAT and data["observation"]["names"] == layout.names
    q = Perceptron.load(str(path))
    assert q.layout == layout and q.meta == {"task": "test"} and q(obs) == pytest.approx(p(obs))
    path.write_text(json.dumps(dict(data, format="other")))
    with pytest.raises(ValueError, match="w.json"):
        Perceptron.load(str(path))
    with pytest.raises(ValueError):
        Perceptron.from_flat(flat[:-1], layout)


def test_braitenberg_turns_away_from_what_it_sees():
    p = braitenberg()
    free = p(np.zeros(8))
    assert free[0] == pytest.approx(free[1]) and free[0] > 0.3
    right = p(np.array([1.0, 1.0, 0, 0, 0, 0, 0, 0]))     # sensors 0, 1: front right
    left = p(np.array([0, 0, 0, 0, 0, 0, 1.0, 1.0]))
    assert right[0] < right[1] and left[0] > left[1]       # turns left, turns right
    ahead = p(np.array([1.0, 0, 0, 0, 0, 0, 0, 1.0]))
    assert ahead[0] < free[0] and ahead[1] < free[1] and ahead[0] != ahead[1]


@pytest.mark.parametrize("scaling", cmd_vel.SCALINGS)
def test_twist_for_wheels_inverts_wheel_speeds(scaling):
    step = 2 * math.pi / 1000
    for left, right in RNG.uniform(-6.0, 6.0, (50, 2)):
        v, w = cmd_vel.twist_for_wheels(scaling, left, right)
        got = cmd_vel.wheel_speeds(scaling, v, w)
        tol = 0.5 * step + 1e-12 if scaling == "epuck_driver" else 1e-9
        assert got == pytest.approx((left, right), abs=tol)
    assert cmd_vel.wheel_speeds(scaling, *cmd_vel.twist_for_wheels(scaling, 0.0, 0.0)) == \
        pytest.approx((0.0, 0.0))
    assert cmd_vel.wheel_speeds("epuck_driver", *cmd_vel.twist_for_wheels(
        "epuck_driver", 300 * step, -299 * step)) == pytest.approx((300 * step, -299 * step))


def test_blocks_equal_block_robot_by_robot():
    poses = np.column_stack([RNG.uniform(-0.5, 0.5, (12, 2)), RNG.uniform(-3, 3, 12)])
    for count in (1, 3, 5):
        batched = nb.blocks(poses, count, 0.6, groups=3)
        for i in range(12):
            g = i // 4
            others = [j for j in range(4 * g, 4 * g + 4) if j != i]
            assert batched[i] == pytest.approx(nb.block(poses[i], poses[others, :2], count, 0.6),
                                               abs=1e-12)
