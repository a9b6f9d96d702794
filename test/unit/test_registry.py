"""The object registry: handles, names, parents, composed poses; the e-puck's V-REP names."""
import numpy as np
import pytest

from epuck_vrep_compat.compat import vrep_codes as vc
from epuck_vrep_compat.geometry.transforms import quat_from_yaw, quat_rotate
from epuck_vrep_compat.scene import registry as reg
from epuck_vrep_compat.scene.epuck_model import default_model, register_epuck, vrep_suffix


def test_handles_names_and_world_pose():
    r = reg.SceneRegistry()
    a = r.add("base", vc.OBJECT_DUMMY, vc.WORLD, (1.0, 0.0, 0.0), quat_from_yaw(np.pi / 2))
    b = r.add("child", vc.OBJECT_SHAPE, a.handle, (1.0, 0.0, 0.0))
    assert r.handle_of("child") == b.handle and r.handle_of("missing") == -1
    position, quat = r.world_pose(b.handle)
    np.testing.assert_allclose(position, [1.0, 1.0, 0.0], atol=1e-12)
    with pytest.raises(ValueError):
        r.add("child", vc.OBJECT_SHAPE)
    assert r.remove(a.handle) == [a.handle, b.handle]
    assert len(r) == 0


def test_epuck_parts_follow_vrep_naming_and_robot_pose():
    r = reg.SceneRegistry()
    pose = {"p": np.array([0.5, 0.2, 0.0]), "q": quat_from_yaw(0.3)}
    angles = np.array([0.0, 0.0])
    model = default_model()
    robots = [register_epuck(r, model, i, f"ePuck{i}", lambda: (pose["p"], pose["q"]),
                             lambda: angles) for i in range(3)]
    assert vrep_suffix(0) == "" and vrep_suffix(2) == "#1"
    assert r.handle_of("ePuck_leftJoint") == robots[0].handle("leftJoint")
    assert r.handle_of("ePuck_proxSensor7#0") == robots[1].handle("proxSensor7")
    assert r.handle_of("dummy_proxSensor3#1") == robots[2].handle("dummy_proxSensor3")
    assert r.get(robots[0].handle("proxSensor0")).object_type == vc.OBJECT_PROXIMITY_SENSOR
    assert r.get(robots[0].handle("camera")).object_type == vc.OBJECT_VISION_SENSOR
    # a proximity sensor looks along its own z axis (V-REP); it must match the dummy's x axis
    sensor_p, sensor_q = r.world_pose(robots[0].handle("proxSensor2"))
    dummy_p, dummy_q = r.world_pose(robots[0].handle("dummy_proxSensor2"))
    np.testing.assert_allclose(sensor_p, dummy_p, atol=1e-12)
    np.testing.assert_allclose(quat_rotate(sensor_q, [0, 0, 1]), quat_rotate(dummy_q, [1, 0, 0]),
                               atol=1e-12)
    expected = pose["p"] + quat_rotate(pose["q"], list(model.sensors[2].position))
    np.testing.assert_allclose(sensor_p, expected, atol=1e-12)
    # wheels: at angle a, the wheel frame is the base frame turned by a about +y
    angles[:] = (0.7, 0.0)
    _, wheel_q = r.world_pose(robots[0].handle("leftWheel"))
    np.testing.assert_allclose(quat_rotate(wheel_q, [1, 0, 0]),
                               quat_rotate(pose["q"], [np.cos(0.7), 0, -np.sin(0.7)]), atol=1e-12)
