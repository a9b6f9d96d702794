"""At most :data:`MALLOC_ARENAS` glibc malloc arenas in the simulator's process.

glibc gives threads malloc arenas of their own (up to eight per core) and keeps the memory
freed in an arena for that arena alone. rospy serves every service connection and every
subscription on a thread of its own, so requests that build large short-lived answers (a
camera image or a depth buffer as a list of numbers) on ever new threads raised the cell
simulator's resident memory by about 30 MB per round of the ``/vrep`` fuzz suite's queries,
round after round; with two arenas it settles after the second round (``bench/fuzz_memory.py``,
docs/benchmarks.md). The cost is a little more contention for malloc's lock between rospy's
threads; the step loop's work is in the core and allocates little. A ``MALLOC_ARENA_MAX`` in
the environment is the user's choice and wins.
"""
import ctypes
import ctypes.util
import os

MALLOC_ARENAS = 2
_M_ARENA_MAX = -8            # glibc's malloc.h


def limit_malloc_arenas(arenas: int = MALLOC_ARENAS) -> bool:
    """Call before the process starts threads (it binds arenas not yet created). True when
    glibc took the limit; False where ``MALLOC_ARENA_MAX`` is set or there is no glibc."""
    if "MALLOC_ARENA_MAX" in os.environ:
        return False
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6")
        return libc.mallopt(_M_ARENA_MAX, int(arenas)) == 1
    except (OSError, AttributeError):
        return False
