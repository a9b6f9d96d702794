"""The simulator's process limits glibc's malloc arenas (issue 27: memory that settles under
a long /vrep fuzz; the measurement is bench/fuzz_memory.py's). Each case in a process of its
own, since the limit is the process's."""
import os
import subprocess
import sys

CALL = ("from epuck_vrep_compat.ros.node.malloc_arenas import limit_malloc_arenas; "
        "print(limit_malloc_arenas())")


def run(env):
    return subprocess.run([sys.executable, "-c", CALL], env=env, capture_output=True,
                          text=True, check=True).stdout.strip()


def test_glibc_takes_the_limit():
    env = {k: v for k, v in os.environ.items() if k != "MALLOC_ARENA_MAX"}
    assert run(env) == "True"


def test_the_users_malloc_arena_max_wins():
    assert run(dict(os.environ, MALLOC_ARENA_MAX="4")) == "False"


def test_the_node_limits_them_before_anything_else():
    """main() calls it first, before rospy starts a thread."""
    import ast
    import inspect
    from epuck_vrep_compat.ros.node import main as node_main
    body = ast.parse(inspect.getsource(node_main.main)).body[0].body
    first = body[0].value
    assert isinstance(first, ast.Call) and first.func.id == "limit_malloc_arenas"
