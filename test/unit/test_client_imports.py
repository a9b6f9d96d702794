"""Client nodes stay light: the module behind every rosrun script except the simulator imports
without loading the compiled core, pybullet or the simulation (they are /vrep or topic clients,
like a user's code)."""
import ast
import os
import subprocess
import sys

import pytest

from repo import REPO

SCRIPTS = os.path.join(REPO, "scripts")
SIMULATOR = {"epuck_sim"}
HEAVY = ("epuck_vrep_compat._core", "pybullet", "epuck_vrep_compat.sim",
         "epuck_vrep_compat.cell.cell", "epuck_vrep_compat.ros.node.simulator_node")


def script_module(name):
    tree = ast.parse(open(os.path.join(SCRIPTS, name)).read())
    return next(n.module for n in ast.walk(tree)
                if isinstance(n, ast.ImportFrom) and n.module.startswith("epuck_vrep_compat"))


CLIENTS = sorted(set(os.listdir(SCRIPTS)) - SIMULATOR)


@pytest.mark.parametrize("script", CLIENTS)
def test_client_node_does_not_load_the_simulator(script):
    code = (f"import sys, {script_module(script)}; "
            f"print([m for m in sys.modules if m.startswith({HEAVY!r})])")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "[]", f"{script} loads {out.stdout.strip()}"


def test_the_core_names_are_still_exported_lazily():
    code = ("import sys, epuck_vrep_compat as e; a = 'epuck_vrep_compat._core' in sys.modules; "
            "w = e.CollisionWorld; print(a, 'epuck_vrep_compat._core' in sys.modules, "
            "w is e._core.CollisionWorld)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.stdout.split() == ["False", "True", "True"], out.stderr
