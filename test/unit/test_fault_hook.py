"""The test-only fault hook (sim/fault_hook.py, issue 27) without a master: each fault fires as
armed and once, a reset disarms, and the builder adds the hook only when its config asks."""
import os

import pytest

from epuck_vrep_compat.builder.build import SimulationConfig, build_simulation
from epuck_vrep_compat.scene.scene_file import load_scene
from epuck_vrep_compat.sim import fault_hook
from epuck_vrep_compat.sim.fault_hook import FaultHook, InjectedFault
from repo import REPO

WALL = os.path.join(REPO, "test", "worlds", "wall.yaml")


def simulation(fault_hook):
    return build_simulation(load_scene(WALL), SimulationConfig(["ePuck0"], seed=1,
                                                               fault_hook=fault_hook))


def test_not_there_unless_asked():
    sim = simulation(False)
    assert sim.fault_hook is None
    assert not any(isinstance(e, FaultHook) for e in sim.extensions)


def test_a_step_raises_once_after_the_others_stepped():
    sim = simulation(True)
    assert sim.extensions[-1] is sim.fault_hook
    sim.step()
    sim.fault_hook.raise_in_next_step()
    with pytest.raises(InjectedFault, match="simulation step"):
        sim.step()
    assert sim.frame == 2
    sim.step()                              # once: the next step is a step again
    assert sim.frame == 3


@pytest.fixture
def sleeps(monkeypatch):
    """The wall-time sleeps the hook asks for, recorded instead of slept (a block is its
    sleep: timing a step would be a wall-clock limit on a shared machine)."""
    asked = []
    monkeypatch.setattr(fault_hook.time, "sleep", asked.append)
    return asked


def test_a_step_blocks_once(sleeps):
    sim = simulation(True)
    sim.fault_hook.block_next_step(0.2)
    sim.step()
    assert sleeps == [0.2] and sim.frame == 1
    sim.step()
    assert sleeps == [0.2] and sim.frame == 2
    with pytest.raises(ValueError):
        sim.fault_hook.block_next_step(0.0)


def test_the_publish_fault_holds_until_switched_off():
    hook = FaultHook()
    hook.check_publish()
    hook.set_publish_fault(True)
    for _ in range(3):
        with pytest.raises(InjectedFault, match="publish"):
            hook.check_publish()
    hook.set_publish_fault(False)
    hook.check_publish()


def test_a_reset_disarms(sleeps):
    sim = simulation(True)
    sim.fault_hook.raise_in_next_step()
    sim.fault_hook.block_next_step(5.0)
    sim.fault_hook.set_publish_fault(True)
    sim.reset()
    sim.step()
    assert sleeps == []
    assert not sim.fault_hook.publish_fault
