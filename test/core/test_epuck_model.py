"""EpuckModel and ConeSensor value types: V-REP defaults, keyword construction, validation."""
import math

import pytest

from epuck_vrep_compat import _core

YAWS_DEG = [-17.2, -45.9, -90, -151.5, 151.2, 90, 45.8, 17.1]
XY = [(0.035, -0.010), (0.025, -0.025), (0.000, -0.030), (-0.035, -0.020), (-0.035, 0.020),
      (0.000, 0.030), (0.025, 0.025), (0.035, 0.010)]


def test_defaults():
    model = _core.EpuckModel()
    assert (model.wheel_radius_m, model.wheel_separation_m, model.body_radius_m,
            model.body_height_m, model.gravity_m_s2) == (0.02, 0.053, 0.037, 0.045, 9.81)
    assert model.max_wheel_speed_rad_s == pytest.approx(2 * math.pi)
    assert len(model.sensors) == 8
    for sensor, yaw_deg, (x, y) in zip(model.sensors, YAWS_DEG, XY):
        assert sensor.position == pytest.approx((x, y, 0.034))
        assert sensor.yaw_rad == pytest.approx(math.radians(yaw_deg))
        assert sensor.pitch_rad == 0.0


def test_keyword_construction_and_attributes():
    sensor = _core.ConeSensor(position=(0.01, 0.02, 0.03), yaw_rad=0.5, max_range_m=0.1)
    sensor.rings = 3
    sensor.position = (0.0, 0.0, 0.02)
    model = _core.EpuckModel(wheel_radius_m=0.021, sensors=[sensor])
    assert model.wheel_radius_m == 0.021 and model.sensors[0].rings == 3
    assert model.sensors[0].position == (0.0, 0.0, 0.02)


@pytest.mark.parametrize(
    "sensor_kwargs, model_kwargs",
    [({}, dict(wheel_radius_m=0.0)), ({}, dict(body_height_m=math.nan)),
     ({}, dict(sensors=[])), (dict(azimuths=15), {}), (dict(rings=-1), {}),
     (dict(min_range_m=0.06), {}), (dict(half_angle_rad=2.0), {}),
     (dict(yaw_rad=math.inf), {})],
)
def test_invalid_models_are_rejected_by_the_swarm(sensor_kwargs, model_kwargs):
    if sensor_kwargs:
        model_kwargs = dict(sensors=[_core.ConeSensor(**sensor_kwargs)])
    with pytest.raises(ValueError):
        _core.EpuckSwarm(_core.CollisionWorld(), _core.EpuckModel(**model_kwargs), 0)


def test_sensor_position_must_be_three_finite_values():
    with pytest.raises(ValueError):
        _core.ConeSensor(position=(0.0, 0.0))
    with pytest.raises(ValueError):
        _core.ConeSensor().position = (0.0, math.nan, 0.0)


def test_the_clients_copy_of_the_geometry_is_the_models():
    """compat/cmd_vel.py's wheel radius, separation and top speed (for clients, which load no
    core) are the core model's defaults."""
    from epuck_vrep_compat.compat import cmd_vel
    model = _core.EpuckModel()
    assert cmd_vel.WHEEL_RADIUS_M == model.wheel_radius_m
    assert cmd_vel.WHEEL_SEPARATION_M == model.wheel_separation_m
    assert cmd_vel.MAX_WHEEL_SPEED_RAD_S == pytest.approx(model.max_wheel_speed_rad_s, abs=1e-8)
