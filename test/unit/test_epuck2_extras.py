"""The e-puck2 profile's pure pieces: floor regions of the scene file, the driver's LED
commands, its message fields, the extra sensors' model state and the robots' URDF."""
import math
import os
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from epuck_vrep_compat.builder.build import SimulationConfig, build_simulation
from epuck_vrep_compat.epuck.epuck2_sensors import Epuck2Settings
from epuck_vrep_compat.epuck.noise import NoiseSettings
from epuck_vrep_compat.ros.epuck.drivers import epuck2_leds
from epuck_vrep_compat.ros.epuck.drivers import extras_messages as build
from epuck_vrep_compat.ros.epuck.description import robot_urdf
from epuck_vrep_compat.ros.epuck.profiles import EPUCK2_DRIVER, PROFILES
from epuck_vrep_compat.ros.epuck.transforms import robot_child_frames
from epuck_vrep_compat.scene.floor_regions import floor_rgb
from epuck_vrep_compat.scene.scene_file import SceneError, parse_scene

LINE = {"min_m": [-0.5, -0.005], "max_m": [0.5, 0.005], "color": [0, 0, 0]}


def test_floor_regions_later_on_top_else_the_arena_floor():
    scene = parse_scene({"floor_regions": [LINE, {"min_m": [0, -1], "max_m": [1, 1],
                                                  "color": [1, 1, 1]}]})
    rgb = floor_rgb(scene.floor_regions, (0.5, 0.5, 0.5),
                    [[-0.2, 0.0], [0.2, 0.0], [-0.2, 0.5], [2.0, 0.0]])
    np.testing.assert_array_equal(rgb, [[0, 0, 0], [1, 1, 1], [0.5] * 3, [0.5] * 3])


@pytest.mark.parametrize("region, says", [
    ({"min_m": [0, 0], "max_m": [0, 1], "color": [0, 0, 0]}, "below"),
    ({"min_m": [0, 0], "max_m": [1, 1]}, "color"),
    ({"min_m": [0, 0], "max_m": [1, 1], "color": [2, 0, 0]}, "color"),
    ({"min_m": [0, 0], "max_m": [1, 1], "color": [0, 0, 0], "shape": "x"}, "shape")])
def test_unusable_floor_regions_name_the_key(region, says):
    with pytest.raises(SceneError, match="floor_regions\\[0\\]") as error:
        parse_scene({"floor_regions": [region]})
    assert says in str(error.value)


def test_cmd_led_six_entries_and_rgb_leds_twelve_bytes():
    state = epuck2_leds.apply_led_command([0] * 10, [1, 0, 5, 0, 1, 1, 9, 9])
    assert state == [1, 0, 0, 0, 1, 0, 0, 0, 1, 1]
    assert "6 entries" in epuck2_leds.apply_led_command([0] * 10, [1, 1])
    state, colours = epuck2_leds.apply_rgb_command([0] * 10, [100, 0, 0] + [0] * 6 + [0, 0, 250])
    assert [state[k] for k in (1, 3, 5, 7)] == [1, 0, 0, 1]
    assert colours[1] == (1.0, 0.0, 0.0) and colours[7] == (0.0, 0.0, 1.0)
    for length in (0, 11, 13):
        assert "exactly 12 bytes" in epuck2_leds.apply_rgb_command([0] * 10, [1] * length)


def test_imu_orientation_from_the_accelerometer():
    g = 9.81
    roll = 0.3
    msg = build.imu(None, "f", (0.0, g * math.sin(roll), g * math.cos(roll)), (0, 0, 0.5))
    q = msg.orientation
    assert 2 * math.atan2(q.x, q.w) == pytest.approx(roll)
    assert msg.angular_velocity.z == 0.5 and list(msg.orientation_covariance)[0] == 0.01


def test_text_markers_as_the_drivers_format_them():
    assert build.floor(None, "f", [1, 22, 333]).text == "floor: [1, 22, 333]"
    assert build.microphone(None, "f", [0, 1, 2, 3]).text == "mic: [0, 1, 2, 3]"
    speed = build.motor_speed(None, "f", [-5, 7])
    assert speed.text == "speed: [-5, 7]" and speed.pose.position.z == 0.15
    b = build.battery(None, "f", 3.8)
    assert b.percentage == pytest.approx(0.5) and b.present
    assert build.dist_sens(None, "f", 7.0).range == 2.0


def two_robot_sim(seed=4, noise=True):
    scene = parse_scene({"arena": {"size_m": [2.0, 2.0], "wall_height_m": 0.3},
                         "floor_regions": [LINE],
                         "robots": [{"position_m": [0.0, 0.0]},
                                    {"position_m": [0.5, 0.5], "yaw_rad": 1.0}]})
    settings = NoiseSettings()
    settings.enabled = noise
    sim = build_simulation(scene, SimulationConfig(
        ["a", "b"], seed=seed, noise=settings, epuck2=Epuck2Settings(battery_discharge_s=10.0)))
    return sim, sim.epuck2


def test_the_extra_sensors_after_steps_and_after_reset():
    sim, s = two_robot_sim(noise=False)
    for _ in range(20):
        sim.step()
    assert list(s.floor[0]) == [833, 0, 833]     # the centre sensor over the 1 cm black line
    assert s.battery_v[0] == pytest.approx(4.2 - 0.8 * 1.0 / 10.0)
    heading = math.atan2(-s.mag_tesla[1, 1], s.mag_tesla[1, 0])
    assert heading == pytest.approx(1.0)
    assert s.tof_m[0] == pytest.approx((1.0 - 0.035) / math.cos(0.21))
    sim.reset()
    assert s.battery_v[0] == pytest.approx(4.2)


def test_a_robot_added_again_under_a_removed_ones_name_gets_a_full_battery():
    sim, s = two_robot_sim(noise=False)
    sim.epucks.robot_namer = lambda number: "a"       # the next robot is named as the first
    for _ in range(20):
        sim.step()
    assert s.battery_v[0] == pytest.approx(4.2 - 0.08)
    sim.epucks.remove_robot("a")
    sim.epucks.add_robot((0.3, -0.3))
    sim.step()
    names = sim.epucks.robot_names
    assert names == ["b", "a"]
    assert s.battery_v[names.index("a")] == pytest.approx(4.2)           # new, not 1 s old
    assert s.battery_v[names.index("b")] == pytest.approx(4.2 - 0.84 / 10.0)


def test_the_extra_sensors_noise_replays_with_the_seed():
    def run(seed):
        sim, s = two_robot_sim(seed)
        out = []
        for _ in range(30):
            sim.step()
            out.append(np.concatenate((s.tof_m, s.mag_tesla.ravel())))
        return np.array(out)
    a = run(4)
    assert np.array_equal(a, run(4)) and not np.array_equal(a, run(5))


@pytest.mark.parametrize("profile", sorted(PROFILES))
def test_urdf_links_are_the_profiles_frames(profile):
    p = PROFILES[profile]
    sim, _ = two_robot_sim()
    urdf = ET.fromstring(robot_urdf(p, sim, 1))
    links = {link.get("name") for link in urdf.iter("link")}
    expected = {p.frame("b", "base_link")} | {p.frame("b", c)
                                              for c, _, _ in robot_child_frames(p, sim, 1)}
    assert links == expected
    assert (p.frame("b", "base_dist_sens") in links) == (p is EPUCK2_DRIVER)


def test_laid_out_extra_topics_match_genpy_byte_for_byte():
    import io

    import rospy
    from sensor_msgs.msg import Imu

    from epuck_vrep_compat.ros.epuck.drivers.extras import _FIELDS
    from epuck_vrep_compat.ros.epuck.drivers.extras_messages import tilt_quat as _tilt_quat
    from epuck_vrep_compat.ros.epuck.drivers.extras_wire import TextMarkerCache, sentinel_batch
    accel = np.array([[0.0, 1.0, 9.7], [-0.5, 0.2, 9.8]])
    gyro = np.array([[0.1, 0.2, 0.3], [0.0, 0.0, -1.5]])
    frames = ["a/base_link", "bb/base_link"]
    batch = sentinel_batch([build.imu(None, f, (0, 0, 1), (0, 0, 0)) for f in frames],
                           _FIELDS["imu"])
    data = batch.pack(7, 500, accel=accel, gyro=gyro, quat=_tilt_quat(accel))
    for i, f in enumerate(frames):
        expected = build.imu(rospy.Time(7, 500), f, accel[i], gyro[i])
        ours = Imu()
        ours.deserialize(batch.frame(data, i)[4:])
        q, e = ours.orientation, expected.orientation      # vectorised: within rounding
        np.testing.assert_allclose([q.x, q.y, q.z, q.w], [e.x, e.y, e.z, e.w], atol=1e-15)
        ours.orientation = expected.orientation
        buff, mine = io.BytesIO(), io.BytesIO()
        expected.serialize(buff)
        ours.serialize(mine)
        assert mine.getvalue() == buff.getvalue()
    battery = sentinel_batch([build.battery(None, "x", 4.2)], _FIELDS["battery"])
    data = battery.pack(1, 2, voltage=np.array([3.8]), percentage=np.array([0.5]))
    buff = io.BytesIO()
    build.battery(rospy.Time(1, 2), "x", 3.8).serialize(buff)
    assert data[4:] == buff.getvalue()
    cache = TextMarkerCache()
    framed = cache.frame(("r", "floor"), "x", lambda: build.floor(None, "f", [1, 2, 3]), 9, 10)
    buff = io.BytesIO()
    build.floor(rospy.Time(9, 10), "f", [1, 2, 3]).serialize(buff)
    assert framed[4:] == buff.getvalue()
