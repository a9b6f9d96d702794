"""The cell's URDF models (models/*.urdf) in pybullet, against numpy kinematics and models.md.

Expected joint values are copied here from shared/spec/models.md in its own units, so the URDF
files are checked against the spec, not against themselves. pybullet is required: without it
these tests fail and say how to install it; they never skip.
"""
import math
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from epuck_vrep_compat.compat.cell_names import YOUBOT_WHEELS
from epuck_vrep_compat.geometry.transforms import (
    compose, inverse, quat_conj, quat_from_yaw, quat_mul)
from epuck_vrep_compat.geometry.urdf_kinematics import load_urdf_chain
from epuck_vrep_compat.scene import robots

MODELS = {"irb140": robots.IRB140, "comau": robots.COMAU_SMART_SIX, "youbot": robots.YOUBOT}
PRIMITIVES = {"box", "cylinder", "sphere"}
POSE_TOLERANCE = 1e-6     # m and rad
BASE_POSITION = np.array([0.4, -0.3, 0.05])
BASE_QUAT = quat_from_yaw(0.7)
deg = math.radians

# name -> (type, lower, upper, max velocity, effort); spec units converted here
EXPECTED_JOINTS = {
    "irb140": {  # models.md 2.1 (degrees), efforts our estimates (the source has 0)
        f"IRB140_joint{k + 1}": ("revolute", deg(lo), deg(hi), deg(v), effort)
        for k, (lo, hi, v, effort) in enumerate([(-180, 180, 250, 250), (-90, 110, 250, 300),
                                                 (-230, 50, 260, 150), (-200, 200, 360, 60),
                                                 (-115, 115, 360, 60), (-400, 400, 450, 30)])},
    "comau": {  # models.md 3.1 (radians); joint 7 is our gripper (3.4)
        **{f"SIX_joint{k + 1}": ("revolute", lo, hi, v, effort)
           for k, (lo, hi, v, effort) in enumerate([
               (-2.967, 2.967, 2.443, 800), (-1.48, 2.71, 2.792, 1000), (-2.967, 0, 2.967, 500),
               (-3.67, 3.67, 7.854, 100), (-2.27, 2.27, 6.545, 80), (-47.12, 47.12, 9.6, 40)])},
        "SIX_joint7": ("prismatic", 0.0, 0.04, 0.1, 100)},
    "youbot": {  # models.md 4.1-4.3; the pinion is our 16th joint (models/README.md)
        **{f"youBotArmJoint{k}": ("revolute", deg(lo), deg(hi), math.pi / 2, effort)
           for k, (lo, hi, effort) in enumerate([(0, 338, 9.5), (0, 155, 9.5), (-297, 0, 6),
                                                 (0, 205, 2), (0, 335, 1)])},
        "youBotGripperJoint1": ("prismatic", 0.0, 0.0115, 0.1, 1),
        "youBotGripperJoint2": ("prismatic", 0.0, 0.0115, 0.1, 1),
        **{f"rollingJoint_{w}": ("continuous", -math.inf, math.inf, 10, 30)
           for w in YOUBOT_WHEELS},
        **{f"rollerJoint_{w}": ("continuous", -math.inf, math.inf, 15, 0)
           for w in YOUBOT_WHEELS},
        "youBotGripperPinionJoint": ("revolute", 0.0, 2.3, 20, 0.01)},
}


@pytest.fixture(scope="module")
def pb():
    try:
        import pybullet
    except ImportError as error:
        pytest.fail(f"pybullet is not importable ({error}). tools/setup installs pybullet==3.2.7 "
                    "into .venv and the workspace env hook puts it on PYTHONPATH; by hand: "
                    "PYTHONPATH=.venv/lib/python3.11/site-packages", pytrace=False)
    return pybullet


@pytest.fixture
def sim(pb):
    clients = []

    def load(model, fixed_base=None, position=BASE_POSITION, quat=BASE_QUAT, dt=1 / 240,
             substeps=1):
        client = pb.connect(pb.DIRECT)
        clients.append(client)
        pb.setGravity(0, 0, -9.81, physicsClientId=client)
        pb.setPhysicsEngineParameter(fixedTimeStep=dt, numSubSteps=substeps,
                                     physicsClientId=client)
        fixed = model.fixed_base if fixed_base is None else fixed_base
        flags = pb.URDF_USE_INERTIA_FROM_FILE | pb.URDF_USE_IMPLICIT_CYLINDER   # README: loading
        body = pb.loadURDF(str(model.urdf_path), list(position), list(quat), useFixedBase=fixed,
                           flags=flags, physicsClientId=client)
        return Body(pb, client, body)

    yield load
    for client in clients:
        pb.disconnect(client)


class Body:
    """One loaded model: joint indices by name and link frames, in one pybullet client."""

    def __init__(self, pb, client, body):
        self.pb, self.client, self.id = pb, client, body
        self.info = [pb.getJointInfo(body, i, physicsClientId=client)
                     for i in range(pb.getNumJoints(body, physicsClientId=client))]
        self.index = {info[1].decode(): info[0] for info in self.info}
        self.movable = [info for info in self.info if info[2] != pb.JOINT_FIXED]

    def call(self, function, *args, **kwargs):
        return function(self.id, *args, physicsClientId=self.client, **kwargs)

    def step(self):
        self.pb.stepSimulation(physicsClientId=self.client)

    def reset(self, q):
        for name, value in q.items():
            self.call(self.pb.resetJointState, self.index[name], value)

    def link_frames(self):
        """URDF link frames, base included (pybullet's base pose is its inertial frame)."""
        com_p, com_q = self.call(self.pb.getBasePositionAndOrientation)
        local_p, local_q = self.call(self.pb.getDynamicsInfo, -1)[3:5]
        frames = {self.pb.getBodyInfo(self.id, physicsClientId=self.client)[0].decode():
                  compose(com_p, com_q, *inverse(local_p, local_q))}
        for info in self.info:
            state = self.call(self.pb.getLinkState, info[0], computeForwardKinematics=1)
            frames[info[12].decode()] = (np.array(state[4]), np.array(state[5]))
        return frames

    def joint_states(self, names):
        states = self.call(self.pb.getJointStates, [self.index[n] for n in names])
        return np.array([s[0] for s in states]), np.array([s[1] for s in states])


def angle_between(q_a, q_b):
    relative = quat_mul(quat_conj(q_a), q_b)
    return 2.0 * math.asin(min(1.0, np.linalg.norm(relative[:3]) / np.linalg.norm(relative)))


def sample_configurations(chain, count, seed):
    """Zero, both limits, and ``count`` seeded draws inside the limits (continuous: +-2 pi)."""
    rng = np.random.default_rng(seed)
    bounds = [(lim.lower, lim.upper) if math.isfinite(lim.lower) else (-2 * math.pi, 2 * math.pi)
              for lim in (chain.limits[n] for n in chain.joint_names)]
    lower, upper = np.array(bounds).T
    draws = [rng.uniform(lower, upper) for _ in range(count)]
    return [np.zeros(len(bounds)), lower, upper] + draws


@pytest.mark.parametrize("key", MODELS)
def test_pybullet_joints_follow_the_contract_and_the_spec(pb, sim, key):
    model = MODELS[key]
    body = sim(model)
    chain = load_urdf_chain(model.urdf_path)
    names = [info[1].decode() for info in body.movable]
    assert names == list(chain.joint_names)
    assert sorted(names) == sorted(model.joints) and len(set(model.joints)) == len(model.joints)
    if model.fixed_base:
        assert names == list(model.joints)
    assert chain.root == model.base_link
    pb_types = {pb.JOINT_REVOLUTE: ("revolute", "continuous"), pb.JOINT_PRISMATIC: ("prismatic",)}
    for info in body.movable:
        name = info[1].decode()
        joint_type, lower, upper, velocity, effort = EXPECTED_JOINTS[key][name]
        assert joint_type in pb_types[info[2]], name
        assert info[11] == pytest.approx(velocity, abs=1e-6), name
        assert info[10] == pytest.approx(effort, abs=1e-9), name
        if joint_type != "continuous":
            assert (info[8], info[9]) == pytest.approx((lower, upper), abs=1e-6), name
        limits = chain.limits[name]
        assert (limits.lower, limits.upper, limits.velocity, limits.effort) == pytest.approx(
            (lower, upper, velocity, effort), abs=1e-6), name


@pytest.mark.parametrize("key", MODELS)
def test_pybullet_link_frames_match_numpy_kinematics(sim, key):
    model = MODELS[key]
    body = sim(model)
    chain = load_urdf_chain(model.urdf_path)
    assert set(body.link_frames()) == set(chain.link_names)
    for q in sample_configurations(chain, count=4, seed=11):
        body.reset(dict(zip(chain.joint_names, q)))
        expected = chain.forward(q, BASE_POSITION, BASE_QUAT)
        for link, (position, quat) in body.link_frames().items():
            assert np.abs(position - expected[link][0]).max() < POSE_TOLERANCE, link
            assert angle_between(quat, expected[link][1]) < POSE_TOLERANCE, link


def test_kinematics_accepts_names_or_arrays_and_rejects_unknown_joints():
    chain = load_urdf_chain(robots.IRB140.urdf_path)
    q = np.linspace(-0.5, 0.5, 6)
    by_array = chain.forward(q, BASE_POSITION, BASE_QUAT)
    by_name = chain.forward(dict(zip(chain.joint_names, q)), BASE_POSITION, BASE_QUAT)
    at_origin = chain.forward(q)
    for link in chain.link_names:
        np.testing.assert_allclose(by_array[link][0], by_name[link][0], atol=1e-12)
        moved = compose(BASE_POSITION, BASE_QUAT, *at_origin[link])
        np.testing.assert_allclose(by_array[link][0], moved[0], atol=1e-12)
        assert angle_between(by_array[link][1], moved[1]) < 1e-9
    with pytest.raises(ValueError):
        chain.forward({"IRB140_joint7": 0.0})
    with pytest.raises(ValueError):
        chain.forward(np.zeros(5))


def horizontal_reach(frames, link):
    return float(np.hypot(*frames[link][0][:2]))


def test_irb140_shoulder_height_and_stretched_wrist_reach(sim):
    """models.md 2.1: shoulder 0.104 + 0.248 m. Stretched: upper arm and forearm horizontal
    (q2 = 90 deg, q3 = -90 deg), wrist centre (link5 origin) 0.07 + 0.36 + 0.38 = 0.81 m out."""
    chain = load_urdf_chain(robots.IRB140.urdf_path)
    body = sim(robots.IRB140, position=(0, 0, 0), quat=(0, 0, 0, 1))
    stretched = {"IRB140_joint2": deg(90), "IRB140_joint3": deg(-90)}
    body.reset(stretched)
    for frames in (chain.forward(stretched), body.link_frames()):
        assert frames["IRB140_link2"][0][2] == pytest.approx(0.352, abs=1e-6)
        assert horizontal_reach(frames, "IRB140_link5") == pytest.approx(0.81, abs=1e-6)
        assert frames["IRB140_link5"][0][2] == pytest.approx(0.352, abs=1e-6)
    zero = chain.forward()
    np.testing.assert_allclose(zero["IRB140_flange"][0], [0.515, 0, 0.712], atol=1e-9)


def test_comau_shoulder_height_and_stretched_wrist_reach(sim):
    """models.md 3.3: shoulder 0.2014 + 0.2486 m; upper arm horizontal (q2 = 90 deg) and the
    elbow-to-wrist line continuing it (q3 = -atan(0.13 / 0.64707)): 0.15 + 0.59 + 0.66 = 1.40 m."""
    chain = load_urdf_chain(robots.COMAU_SMART_SIX.urdf_path)
    body = sim(robots.COMAU_SMART_SIX, position=(0, 0, 0), quat=(0, 0, 0, 1))
    stretched = {"SIX_joint2": math.pi / 2, "SIX_joint3": -math.atan2(0.13, 0.64707)}
    body.reset(stretched)
    for frames in (chain.forward(stretched), body.link_frames()):
        assert frames["SIX_link2"][0][2] == pytest.approx(0.45, abs=1e-6)
        assert horizontal_reach(frames, "SIX_link5") == pytest.approx(1.40, abs=1e-3)
        assert frames["SIX_link5"][0][2] == pytest.approx(0.45, abs=1e-6)
    np.testing.assert_allclose(chain.forward()["SIX_link5"][0], [0.02, 0, 1.68707], atol=1e-9)


def test_youbot_wheels_arm_mount_and_candle_pose():
    """models.md 4.1: wheels (+-0.228, +-0.158, -0.034), arm mount (0.143, 0, 0.046); 4.2: the
    joint angles that undo each origin rotation put the arm straight up."""
    chain = load_urdf_chain(robots.YOUBOT.urdf_path)
    frames = chain.forward()
    for wheel, (sx, sy) in zip(YOUBOT_WHEELS, [(1, 1), (-1, 1), (-1, -1), (1, -1)]):
        np.testing.assert_allclose(frames[f"youBotWheel_{wheel}"][0],
                                   [sx * 0.228, sy * 0.158, -0.034], atol=1e-12)
    np.testing.assert_allclose(frames["youBotArmLink0"][0], [0.143, 0, 0.046], atol=1e-12)
    candle = dict(zip(robots.YOUBOT.joints, np.radians([169, 65, -146, 102.5, 167.5])))
    frames = chain.forward(candle)
    column = np.array([frames[f"youBotArmLink{k}"][0] for k in range(2, 6)])
    np.testing.assert_allclose(np.diff(column[:, 2]), [0.155, 0.135, 0.130], atol=1e-9)
    np.testing.assert_allclose(column[1:3, :2], column[[0, 0], :2], atol=1e-9)
    assert np.linalg.norm(column[3, :2] - column[0, :2]) == pytest.approx(0.002, abs=1e-8)


def control_targets(chain):
    """A target at 75 % of each actuated joint's range (continuous: one turn); passive: None."""
    targets = {}
    for name in chain.joint_names:
        limits = chain.limits[name]
        if limits.effort == 0:
            targets[name] = None
        elif math.isfinite(limits.lower):
            targets[name] = limits.lower + 0.75 * (limits.upper - limits.lower)
        else:
            targets[name] = 2 * math.pi
    return targets


def command(body, chain, targets):
    pb = body.pb
    for name, target in targets.items():
        limits = chain.limits[name]
        if target is None:     # passive: switch pybullet's default velocity motor off
            body.call(pb.setJointMotorControl2, body.index[name], pb.VELOCITY_CONTROL, force=0)
        else:
            body.call(pb.setJointMotorControl2, body.index[name], pb.POSITION_CONTROL,
                      targetPosition=target, maxVelocity=limits.velocity, force=limits.effort)


@pytest.mark.parametrize("dt, substeps", [(1 / 240, 1), (0.05, 12)])
@pytest.mark.parametrize("key", MODELS)
def test_position_control_respects_velocity_limits_and_settles(sim, key, dt, substeps):
    model = MODELS[key]
    chain = load_urdf_chain(model.urdf_path)
    body = sim(model, fixed_base=True, dt=dt, substeps=substeps)
    targets = control_targets(chain)
    command(body, chain, targets)
    driven = [n for n, t in targets.items() if t is not None]
    goal = np.array([targets[n] for n in driven])
    v_max = np.array([chain.limits[n].velocity for n in driven])
    lower = np.array([chain.limits[n].lower for n in driven])
    upper = np.array([chain.limits[n].upper for n in driven])
    prismatic = np.array([n in {j.name for j in chain.joints if j.joint_type == "prismatic"}
                          for n in driven])
    # The youBot's arm starts on its mechanical stops: pybullet's soft limit lets gravity push
    # one joint 2.5 mrad past its stop before the motor lifts it.
    overrun = np.where(prismatic, 5e-4, 5e-3)     # m, rad
    peak = np.zeros(len(driven))
    for _ in range(int(round(10.0 / dt))):
        body.step()
        q, v = body.joint_states(driven)
        assert np.all(np.isfinite(q)) and np.all(np.isfinite(v))
        assert np.all(q > lower - overrun) and np.all(q < upper + overrun), dict(zip(driven, q))
        peak = np.maximum(peak, np.abs(v))
    assert np.all(peak <= 1.05 * v_max), dict(zip(driven, peak / v_max))
    slowest = np.argmax(np.abs(goal) / v_max)    # all start at 0: it cruises longest
    assert peak[slowest] >= 0.95 * v_max[slowest], driven[slowest]
    tolerance = np.where(prismatic, 1e-4, 2e-3)    # m, rad: static error under gravity
    assert np.all(np.abs(q - goal) < tolerance), dict(zip(driven, q - goal))
    assert np.all(np.abs(v) < 1e-3), dict(zip(driven, v))


@pytest.mark.parametrize("dt, substeps", [(1 / 240, 1), (0.05, 12)])
def test_youbot_rests_on_its_wheels_while_the_arm_moves(pb, sim, dt, substeps):
    """Floating base on a plane: the arm goes to its 75 % targets, the base stays put."""
    chain = load_urdf_chain(robots.YOUBOT.urdf_path)
    axle_height = 0.0475 + 0.034
    body = sim(robots.YOUBOT, position=(0, 0, axle_height), quat=(0, 0, 0, 1), dt=dt,
               substeps=substeps)
    pb.createMultiBody(0, pb.createCollisionShape(pb.GEOM_PLANE, physicsClientId=body.client),
                       physicsClientId=body.client)
    targets = control_targets(chain)
    targets.update({f"rollingJoint_{w}": 0.0 for w in YOUBOT_WHEELS})
    command(body, chain, targets)
    for _ in range(int(round(10.0 / dt))):
        body.step()
        position, quat = body.link_frames()["youBot"]
        assert abs(position[2] - axle_height) < 0.005
        assert np.hypot(*position[:2]) < 0.01
        assert angle_between(quat, (0, 0, 0, 1)) < 0.02
    linear, angular = body.call(pb.getBaseVelocity)
    assert np.abs(linear).max() < 1e-3 and np.abs(angular).max() < 1e-3


def urdf_links(model):
    return ET.parse(model.urdf_path).getroot().findall("link")


@pytest.mark.parametrize("key", MODELS)
def test_urdf_shapes_are_primitives_and_inertias_physical(key):
    for link in urdf_links(MODELS[key]):
        name = link.get("name")
        for element in link.findall("collision") + link.findall("visual"):
            shapes = [child.tag for child in element.find("geometry")]
            assert len(shapes) == 1 and shapes[0] in PRIMITIVES, (name, shapes)
        inertial = link.find("inertial")
        assert inertial is not None, name
        assert float(inertial.find("mass").get("value")) > 0, name
        inertia = {k: float(v) for k, v in inertial.find("inertia").attrib.items()}
        principal = np.array([inertia["ixx"], inertia["iyy"], inertia["izz"]])
        assert np.all(principal > 0), name
        assert inertia["ixy"] == inertia["ixz"] == inertia["iyz"] == 0, name
        assert np.all(2 * principal <= principal.sum() * (1 + 1e-9)), name   # triangle inequality


@pytest.mark.parametrize("key", MODELS)
def test_pybullet_sees_primitive_shapes_and_file_masses(pb, sim, key):
    body = sim(MODELS[key], fixed_base=False)    # pybullet gives a fixed base zero mass
    primitives = {pb.GEOM_BOX, pb.GEOM_CYLINDER, pb.GEOM_SPHERE}
    for link in [-1] + [info[0] for info in body.info]:
        mass, _, inertia = body.call(pb.getDynamicsInfo, link)[:3]
        assert mass > 0 and min(inertia) > 0, link
        shapes = body.call(pb.getCollisionShapeData, link)
        assert all(shape[2] in primitives for shape in shapes), link
