"""The supervisor's arithmetic (ISO/TS 15066 S_p, the speed scale and its hold) and the
simulator's side of it (no master): the speed scale slows and holds an arm, the separation
query agrees between the operator's objects and his body placed by value."""
import math
import os

import numpy as np
import pytest

from epuck_vrep_compat.builder.build import build_simulation
from epuck_vrep_compat.cell.separation import NoOperator, operator_separation
from epuck_vrep_compat.nodes.ssm_model import (
    ArmGovernor, SsmParameters, operator_uncertainty, protective_separation,
    static_separation)
from epuck_vrep_compat.scene.scene_file import load_scene
from repo import REPO


def test_protective_separation_adds_the_standards_terms():
    p = SsmParameters()
    # S_h = 1.6 (0.2 + 0.3) = 0.8; C 0.1; Z_d 0.05; Z_r 0.02
    assert static_separation(p, 0.05) == pytest.approx(0.97)
    # S_r + S_s = 0.5 (0.2 + 0.15)
    assert protective_separation(p, 0.05, 0.5) == pytest.approx(0.97 + 0.175)


def test_operator_uncertainty_is_k_sigma_of_the_worst_direction():
    p = SsmParameters(tracker_sigmas=2.0, min_operator_uncertainty_m=0.01)
    assert operator_uncertainty(p) == 0.01
    assert operator_uncertainty(p, [[0.04, 0.0], [0.0, 0.01]]) == pytest.approx(0.4)
    rotated = np.array([[0.025, 0.015], [0.015, 0.025]])        # eigenvalues 0.04, 0.01
    assert operator_uncertainty(p, rotated) == pytest.approx(0.4)


def test_the_scale_keeps_s_p_within_the_separation_and_holds_after_a_stop():
    p = SsmParameters()
    g = ArmGovernor(p)
    s_p0, band = static_separation(p, 0.0), 1.0 * (0.2 + 0.15)
    assert g.update(s_p0 + 0.5 * p.resume_margin_m, 0.0) == 0.0   # fail safe start: held ...
    d = s_p0 + p.resume_margin_m + 0.5 * band          # ... until clear of S_p0 + margin,
    rising = [g.update(d, 0.0) for _ in range(9)]      # then from restart_scale, doubling
    assert rising[:3] == pytest.approx([p.restart_scale, 2 * p.restart_scale,
                                        4 * p.restart_scale])
    assert rising[-1] == pytest.approx((p.resume_margin_m + 0.5 * band) / band)
    for d in np.linspace(s_p0 + band, s_p0, 7):
        scale = g.update(d, 0.0)
        assert protective_separation(p, 0.0, scale * g.reference_speed_m_s) <= d + 1e-12
    g.scale = 0.6
    assert g.update(s_p0 + 3 * band, 0.0) == 1.0
    assert g.update(s_p0 - 0.01, 0.0) == 0.0 and g.stopped
    assert g.update(s_p0 + 0.5 * p.resume_margin_m, 0.0) == 0.0     # hysteresis
    assert g.update(math.nan, 0.0) == 0.0


def test_the_scale_keeps_s_p_within_the_separation_at_the_end_of_its_horizon():
    """A scale in effect h after the separation was measured: the operator (v_h) and the
    robot (s v_ref) approach meanwhile, and S_p must still hold then."""
    p = SsmParameters()
    g = ArmGovernor(p)
    g.reference_speed_m_s = 1.5
    h = 0.1
    s_p0 = static_separation(p, 0.0)
    for d in np.linspace(s_p0, s_p0 + 2.0, 41):
        g.scale, g.stopped = 1.0, False                 # no rise limit, no hold
        scale = g.update(d, 0.0, h)
        v_r = scale * g.reference_speed_m_s
        if scale > 0.0:                                 # a held robot needs no S_p
            assert protective_separation(p, 0.0, v_r) <= (
                d - (p.human_speed_m_s + v_r) * h + 1e-12)
        g.scale, g.stopped = 1.0, False
        assert scale <= g.update(d, 0.0) + 1e-12        # never faster than without a horizon
    assert g.update(s_p0 + p.human_speed_m_s * h, 0.0, h) == 0.0 and g.stopped
    assert g.update(s_p0 + p.human_speed_m_s * h + 0.5 * p.resume_margin_m, 0.0, h) == 0.0
    band = 1.5 * (p.reaction_time_s + 0.5 * p.stopping_time_s + h)
    g.scale, g.stopped = 1.0, False
    assert g.update(s_p0 + p.human_speed_m_s * h + band, 0.0, h) == pytest.approx(1.0)


def test_the_reference_speed_learns_the_fastest_speed_per_unit_scale():
    g = ArmGovernor(SsmParameters(reference_speed_m_s=0.5))
    g.scale = 0.5
    g.learn_speed(0.4)
    assert g.reference_speed_m_s == pytest.approx(0.8)
    g.learn_speed(0.1)
    assert g.reference_speed_m_s == pytest.approx(0.8)
    g.scale = 0.01                          # the first step after a stop: the arm catches up
    g.learn_speed(0.045)
    assert g.reference_speed_m_s == pytest.approx(4.5)
    g.scale = 0.0                                         # held: nothing to learn
    g.learn_speed(0.2)
    assert g.reference_speed_m_s == pytest.approx(4.5)


def test_a_learnt_speed_is_forgotten_after_its_memory():
    g = ArmGovernor(SsmParameters(reference_speed_m_s=0.5, speed_memory_s=2.0))
    g.scale = 0.02
    g.learn_speed(0.09, now_s=1.0)                        # catching up: 4.5 per unit scale
    g.scale = 0.5
    g.learn_speed(0.4, now_s=2.0)                         # on its path: 0.8
    assert g.reference_speed_m_s == pytest.approx(4.5)
    g.learn_speed(0.1, now_s=3.0)
    assert g.reference_speed_m_s == pytest.approx(4.5)
    g.learn_speed(0.1, now_s=3.5)                         # 4.5 is 2.5 s old: gone
    assert g.reference_speed_m_s == pytest.approx(0.8)
    g.scale = 0.0
    g.learn_speed(0.0, now_s=10.0)                        # held long: back to the floor
    assert g.reference_speed_m_s == pytest.approx(0.5)


@pytest.mark.parametrize("field, value", [("reaction_time_s", -0.1), ("intrusion_m", math.nan),
                                          ("reference_speed_m_s", 0.0),
                                          ("restart_scale", 0.0), ("restart_scale", 1.5)])
def test_bad_parameters_are_named(field, value):
    with pytest.raises(ValueError, match=field):
        SsmParameters(**{field: value}).check()


@pytest.fixture(scope="module")
def sim():
    simulation = build_simulation(load_scene(os.path.join(REPO, "worlds", "merlin_safety.yaml")))
    yield simulation
    simulation.cell.close()


def test_the_speed_scale_slows_and_holds_the_script(sim):
    irb = sim.cell.arm_by_name["IRB140"]
    for _ in range(10):
        sim.step()
    irb.set_speed_scale(0.0)
    for _ in range(5):
        sim.step()
    held, t_held = irb.q.copy(), irb.script_time
    for _ in range(20):
        sim.step()
    assert irb.script_time == t_held
    np.testing.assert_allclose(irb.q, held, atol=2e-3)
    assert np.abs(irb.qd).max() < 0.01
    irb.set_speed_scale(0.5)
    sim.step()
    assert irb.script_time == pytest.approx(t_held + 0.5 * sim.step_s)
    irb.set_speed_scale(7.0)
    assert irb.speed_scale == 1.0


def test_the_speed_scale_slows_commanded_velocities_and_the_base(sim):
    irb = sim.cell.arm_by_name["IRB140"]
    joint = sim.registry.get(sim.registry.handle_of("IRB140_joint1")).properties["joint"]
    joint.set_target_velocity(0.4)                    # a client's command: the script stops
    irb.set_speed_scale(0.5)
    for _ in range(10):
        sim.step()
    assert irb.qd[joint.index] == pytest.approx(0.2, abs=0.01)
    bot = sim.cell.arm_by_name["youBot"]
    bot.set_twist(0.2, 0.0, 0.0)
    bot.set_speed_scale(0.25)
    x0 = bot.base_xy_yaw.copy()
    for _ in range(20):
        sim.step()
    moved = np.hypot(*(bot.base_xy_yaw[:2] - x0[:2]))
    assert moved == pytest.approx(0.25 * 0.2 * 20 * sim.step_s, rel=1e-6)
    irb.set_speed_scale(1.0)
    bot.set_speed_scale(1.0)


def test_separation_of_the_operator_and_of_his_body_placed_where_he_is(sim):
    truth = operator_separation(sim.cell)
    x, y, _, _ = sim.cell.operator.state()
    placed = operator_separation(sim.cell, False, x, y)
    assert [s.link for s in truth] == [s.link for s in placed]
    np.testing.assert_allclose([s.distance_m for s in truth], [s.distance_m for s in placed],
                               atol=1e-9)
    assert {s.robot for s in truth} == {"IRB140", "SIX", "youBot"}
    moved = operator_separation(sim.cell, False, x - 1.0, y)
    assert min(s.distance_m for s in moved) != min(s.distance_m for s in truth)
    with pytest.raises(ValueError, match="not finite"):
        operator_separation(sim.cell, False, math.nan, 0.0)


def test_no_operator_no_ground_truth(sim):
    operator, handles = sim.cell.operator, sim.cell.operator_handles
    sim.cell.operator = None
    try:
        with pytest.raises(NoOperator):
            operator_separation(sim.cell)
    finally:
        sim.cell.operator = operator
    assert handles
