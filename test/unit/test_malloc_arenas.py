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


# a depth buffer's size, allocated, freed, allocated again: where did glibc put the second?
REUSE = """
import ctypes, sys
from epuck_vrep_compat.ros.node.malloc_arenas import map_large_buffers
class Info(ctypes.Structure):
    _fields_ = [(n, ctypes.c_size_t) for n in ("arena ordblks smblks hblks hblkhd usmblks "
                                               "fsmblks uordblks fordblks keepcost").split()]
libc = ctypes.CDLL("libc.so.6")
libc.mallinfo2.restype = Info
if sys.argv[1] == "mapped":
    assert map_large_buffers()
first = bytearray(640 * 480 * 4)
del first
second = bytearray(640 * 480 * 4)
print(libc.mallinfo2().hblkhd >= len(second))
"""


def mapped_again(how):
    env = {k: v for k, v in os.environ.items() if k != "MALLOC_MMAP_THRESHOLD_"}
    return subprocess.run([sys.executable, "-c", REUSE, how], env=env, capture_output=True,
                          text=True, check=True).stdout.strip()


def test_large_buffers_stay_mapped_after_one_is_freed():
    """The bound on the cell's resident memory (docs/parameters.md, Bounds): every buffer of
    256 KB or more is a mapping of its own, given back at its free, so buffers freed in another
    order than they came leave no holes in the arenas. glibc's default (the control) serves the
    second depth buffer from an arena."""
    assert mapped_again("mapped") == "True"
    assert mapped_again("default") == "False"


def test_the_users_mmap_threshold_wins():
    env = dict(os.environ, MALLOC_MMAP_THRESHOLD_="1048576")
    out = subprocess.run([sys.executable, "-c", "from epuck_vrep_compat.ros.node.malloc_arenas "
                          "import map_large_buffers; print(map_large_buffers())"], env=env,
                         capture_output=True, text=True, check=True).stdout.strip()
    assert out == "False"


def test_the_node_limits_them_before_anything_else():
    """main() calls it first, before rospy starts a thread."""
    import ast
    import inspect
    from epuck_vrep_compat.ros.node import main as node_main
    body = ast.parse(inspect.getsource(node_main.main)).body[0].body
    first, second = body[0].value, body[1].value
    assert isinstance(first, ast.Call) and first.func.id == "limit_malloc_arenas"
    assert isinstance(second, ast.Call) and second.func.id == "map_large_buffers"
