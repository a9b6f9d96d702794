"""simLoadModel of the cell's robots (no master): an IRB 140, a SMART SiX or a youBot by V-REP's
model file name or our URDF's, named as V-REP names a copy, working (joints, collision shapes,
the youBot's wheels), and removed whole; refused cleanly where there is no cell."""
import numpy as np
import pytest

from epuck_vrep_compat.cell.devices.mecanum import wheel_speeds
from epuck_vrep_compat.cell.separation import operator_separation
from epuck_vrep_compat.vrep.backend import VrepError


@pytest.fixture
def backend(backend_of):
    return backend_of("merlin_cell.yaml")


def joint(sim, name):
    return sim.registry.get(sim.registry.handle_of(name)).properties["joint"]


@pytest.mark.parametrize("file_name, base, a_joint", [
    ("models/robots/non-mobile/ABB IRB 140.ttm", "IRB140#0", "IRB140_joint3#0"),
    ("irb140.urdf", "IRB140#0", "IRB140_joint3#0"),
    ("COMAU SMART SiX.ttm", "SIX#0", "SIX_joint3#0"),
    ("KUKA YouBot.ttm", "youBot#0", "youBotArmJoint3#0")])
def test_a_loaded_robot_is_named_as_a_copy_and_its_joints_work(backend, file_name, base,
                                                               a_joint):
    sim = backend.sim
    parts = backend.load_model(file_name)
    assert parts.root.name == base and sim.registry.handle_of(base) == parts.root.handle
    assert base in sim.cell.arm_by_name and sim.cell.arm_by_name[base].spec.script == "none"
    j = joint(sim, a_joint)
    target = 0.5 * (j.lower + j.upper) + 0.1
    j.set_target_position(target)
    for _ in range(60):
        sim.step()
    assert j.position() == pytest.approx(target, abs=2e-3)
    links = {s.link for s in operator_separation(sim.cell) if s.robot == base}
    assert links and all(link.endswith("#0") for link in links)   # its shapes are in the world
    removed = backend.remove_object(parts.root.handle)
    assert sim.registry.handle_of(a_joint) == -1 and base not in sim.cell.arm_by_name
    assert not any(sim.world.has(h) for h in removed)
    sim.step()


def test_copies_count_up_and_a_free_name_is_used_as_it_is(backend):
    sim = backend.sim
    assert backend.load_model("ABB IRB 140.ttm").root.name == "IRB140#0"
    assert backend.load_model("ABB IRB 140.ttm").root.name == "IRB140#1"
    backend.remove_object(sim.registry.handle_of("IRB140"))
    assert backend.load_model("irb140.urdf").root.name == "IRB140"
    assert sim.registry.handle_of("IRB140_joint1") >= 0


def test_a_loaded_youbot_drives_on_its_wheels(backend):
    sim = backend.sim
    bot = sim.cell.arm_by_name[backend.load_model("youbot.urdf").root.name]
    for w, omega in wheel_speeds(0.0, 0.2, 0.0).items():
        joint(sim, f"rollingJoint_{w}#0").set_target_velocity(omega)
    y0 = bot.base_xy_yaw[1]
    for _ in range(20):
        sim.step()
    assert bot.base_xy_yaw[1] - y0 == pytest.approx(0.2 * 20 * sim.step_s, abs=1e-9)
    assert np.isfinite(bot.link_position).all()


def test_no_cell_no_cell_robot(backend_of):
    b = backend_of("arena.yaml")
    with pytest.raises(VrepError, match="nothing in this scene loads 'cell_robot'"):
        b.load_model("ABB IRB 140.ttm")
