"""simRosGetObjectGroupData's data types 0..19 over a two-robot scene (no master)."""
import math

import numpy as np
import pytest

from epuck_vrep_compat.builder.build import SimulationConfig, build_simulation
from epuck_vrep_compat.compat import vrep_codes as vc
from epuck_vrep_compat.geometry.transforms import quat_from_axis_angle, quat_from_yaw, quat_mul
from epuck_vrep_compat.scene.scene_file import parse_scene
from epuck_vrep_compat.sim.control import SimulationControl
from epuck_vrep_compat.vrep.backend import VrepBackend, VrepError
from epuck_vrep_compat.vrep.group_data import group_data, vrep_euler_angles
from repo import REPO

SCENE = {"arena": {"size_m": [2.0, 2.0]},
         "robots": [{"position_m": [0.1, 0.2], "yaw_rad": 0.5},
                    {"position_m": [-0.5, -0.5], "yaw_rad": 0.0}]}


@pytest.fixture
def backend():
    sim = build_simulation(parse_scene(SCENE), SimulationConfig(["ePuck0", "ePuck1"]))
    return VrepBackend(sim, SimulationControl(sim), real_time=True)


def handle(backend, name):
    return backend.object_handle(name)


def test_names_types_and_parents_cover_every_object(backend):
    everything = [o.handle for o in backend.sim.registry.objects()]
    handles, ints, floats, names = group_data(backend, vc.APPOBJ_OBJECT, 0)
    assert handles == everything and ints == [] and floats == []
    assert names == [backend.object_name(h) for h in everything]
    assert "ePuck_leftJoint" in names and "ePuck_proxSensor0#0" in names
    _, types, _, _ = group_data(backend, vc.APPOBJ_OBJECT, 1)
    assert types == [backend.object_type(h) for h in everything]
    _, parents, _, _ = group_data(backend, vc.APPOBJ_OBJECT, 2)
    assert parents[everything.index(handle(backend, "ePuck"))] == vc.WORLD
    assert parents[everything.index(handle(backend, "ePuck_leftJoint#0"))] == \
        handle(backend, "ePuck#0")


def test_every_object_of_a_type_not_only_the_first(backend):
    handles, _, _, names = group_data(backend, vc.OBJECT_JOINT, 0)
    assert names == ["ePuck_leftJoint", "ePuck_rightJoint", "ePuck_leftJoint#0",
                     "ePuck_rightJoint#0"]
    assert len(handles) == 4
    assert group_data(backend, vc.OBJECT_GRAPH, 3) == ([], [], [], [])


def test_positions_absolute_and_relative_to_parent(backend):
    handles, _, absolute, _ = group_data(backend, vc.OBJECT_SHAPE, 3)
    base = handles.index(handle(backend, "ePuck"))
    np.testing.assert_allclose(absolute[3 * base:3 * base + 3], [0.1, 0.2, 0.0], atol=1e-6)
    handles, _, relative, _ = group_data(backend, vc.OBJECT_JOINT, 4)
    np.testing.assert_allclose(relative[0:3], [0.0, 0.0265, 0.020], atol=1e-6)
    np.testing.assert_allclose(relative[6:9], [0.0, 0.0265, 0.020], atol=1e-6)


def test_orientations_euler_quaternion_and_the_plugins_pose_bug(backend):
    handles, _, quats, _ = group_data(backend, vc.OBJECT_SHAPE, 7)
    base = handles.index(handle(backend, "ePuck"))
    np.testing.assert_allclose(quats[4 * base:4 * base + 4], quat_from_yaw(0.5), atol=1e-6)
    _, _, euler, _ = group_data(backend, vc.OBJECT_SHAPE, 5)
    np.testing.assert_allclose(euler[3 * base:3 * base + 3], [0.0, 0.0, 0.5], atol=1e-6)
    _, _, pose_e, _ = group_data(backend, vc.OBJECT_SHAPE, 9)
    _, _, pose_q, _ = group_data(backend, vc.OBJECT_SHAPE, 11)
    assert len(pose_e) == 6 * len(handles) and len(pose_q) == 7 * len(handles)
    # 11/12 reproduce the plugin: Euler angles and a 0.0 where the quaternion should be
    np.testing.assert_allclose(pose_q[7 * base:7 * base + 7], [0.1, 0.2, 0.0, 0.0, 0.0, 0.5, 0.0],
                               atol=1e-6)
    _, _, rel, _ = group_data(backend, vc.OBJECT_JOINT, 12)
    np.testing.assert_allclose(rel[3:6], [-math.pi / 2, 0.0, 0.0], atol=1e-6)   # axis = +y


def test_vrep_euler_angles_are_x_then_y_then_z():
    alpha, beta, gamma = 0.3, -0.4, 1.2
    q = quat_mul(quat_mul(quat_from_axis_angle((1, 0, 0), alpha),
                          quat_from_axis_angle((0, 1, 0), beta)),
                 quat_from_axis_angle((0, 0, 1), gamma))
    np.testing.assert_allclose(vrep_euler_angles(q), [alpha, beta, gamma], atol=1e-12)
    locked = vrep_euler_angles(quat_mul(quat_from_axis_angle((0, 1, 0), math.pi / 2),
                                        quat_from_axis_angle((0, 0, 1), 0.2)))
    assert locked[1] == pytest.approx(math.pi / 2) and all(map(math.isfinite, locked))


def test_sensor_and_joint_data_with_fillers_for_other_objects(backend):
    handles, ints, floats, _ = group_data(backend, vc.APPOBJ_OBJECT, 13)
    assert len(ints) == 2 * len(handles) and len(floats) == 6 * len(handles)
    types = [backend.object_type(h) for h in handles]
    for k, object_type in enumerate(types):
        if object_type != vc.OBJECT_PROXIMITY_SENSOR:
            assert ints[2 * k:2 * k + 2] == [-1, -1] and floats[6 * k:6 * k + 6] == [0.0] * 6
        else:
            assert ints[2 * k] in (0, 1)
    handles, ints, floats, _ = group_data(backend, vc.APPOBJ_OBJECT, 14)
    assert ints == [-1] * len(handles) and floats == [0.0] * 6 * len(handles)
    handles, ints, floats, _ = group_data(backend, vc.OBJECT_JOINT, 16)
    assert ints == [vc.JOINT_REVOLUTE, vc.JOINTMODE_FORCE] * 4
    assert floats == pytest.approx([-math.pi, -1.0] * 4)
    _, ints, floats, _ = group_data(backend, vc.OBJECT_SHAPE, 16)
    assert set(ints) == {-1} and set(floats) == {0.0}


def test_joint_state_and_velocities_follow_the_motion(backend):
    left = handle(backend, "ePuck_leftJoint")
    backend.joint_command(left, "target_velocity", 4.0)
    backend.joint_command(handle(backend, "ePuck_rightJoint"), "target_velocity", 4.0)
    for _ in range(10):
        backend.sim.step()
    handles, _, floats, _ = group_data(backend, vc.OBJECT_JOINT, 15)
    position, _effort = floats[0:2]
    assert position == pytest.approx(backend.joint_state(left)[0]) and position != 0.0
    handles, _, linear, _ = group_data(backend, vc.OBJECT_SHAPE, 17)
    base = handles.index(handle(backend, "ePuck"))
    speed = np.hypot(*linear[3 * base:3 * base + 2])
    assert speed == pytest.approx(4.0 * backend.sim.epucks.model.wheel_radius_m, rel=0.05)
    _, _, twist, _ = group_data(backend, vc.OBJECT_SHAPE, 19)
    _, _, angular, _ = group_data(backend, vc.OBJECT_SHAPE, 18)
    assert twist[6 * base:6 * base + 3] == linear[3 * base:3 * base + 3]
    assert twist[6 * base + 3:6 * base + 6] == angular[3 * base:3 * base + 3]


@pytest.mark.parametrize("object_type, data_type", [
    (108, 0), (-2, 0), (115, 0), (1000, 1), (vc.APPOBJ_OBJECT, 20), (vc.APPOBJ_OBJECT, -1)])
def test_bad_types_raise(backend, object_type, data_type):
    with pytest.raises(VrepError):
        group_data(backend, object_type, data_type)


def test_batched_poses_equal_one_pose_call_per_object_in_the_cell():
    """group_data composes each world pose once and shares it with the descendants; relative
    poses are local poses. Both must equal simRosGetObjectPose's answer, object by object,
    on the deepest scene there is (arms of up to 16 joints) in a moved configuration."""
    import os

    from epuck_vrep_compat.scene.scene_file import load_scene
    from epuck_vrep_compat.sim.control import RUNNING

    world = os.path.join(REPO, "worlds", "merlin_cell.yaml")
    sim = build_simulation(load_scene(world))
    try:
        backend = VrepBackend(sim, SimulationControl(sim, RUNNING), real_time=True)
        for _ in range(40):
            sim.step()
        for data_type, frame in ((9, vc.WORLD), (10, vc.HANDLE_PARENT)):
            handles, _, floats, _ = group_data(backend, vc.APPOBJ_OBJECT, data_type)
            got = np.array(floats).reshape(-1, 6)
            for row, h in zip(got, handles):
                p, q = backend.pose(h, frame)
                np.testing.assert_allclose(row[:3], p, atol=1e-12, err_msg=backend.object_name(h))
                turn = (row[3:] - vrep_euler_angles(q) + math.pi) % (2 * math.pi) - math.pi
                np.testing.assert_allclose(turn, 0.0, atol=1e-9, err_msg=backend.object_name(h))
    finally:
        sim.cell.close()
