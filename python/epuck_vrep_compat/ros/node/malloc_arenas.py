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

Large buffers (a Kinect depth buffer of 640 x 480 floats is 1.2 MB, its colour image 0.9 MB) are
mapped and unmapped on their own (:func:`map_large_buffers`): glibc's default raises its mapping
threshold to the size of the first such buffer freed, and then serves the rest from the arenas,
where a buffer freed below one still in use cannot be given back; in issue 27's hour-long soak
the cell's simulator, its Kinect read 20 times a second, rose in steps of about a depth buffer's
size (1.1-1.2 MB) every 10-15 minutes after the first half hour. ``MALLOC_MMAP_THRESHOLD_`` in
the environment wins.
"""
import ctypes
import ctypes.util
import os

MALLOC_ARENAS = 2
LARGE_BUFFER_BYTES = 256 * 1024
_M_ARENA_MAX = -8            # glibc's malloc.h
_M_MMAP_THRESHOLD = -3


def limit_malloc_arenas(arenas: int = MALLOC_ARENAS) -> bool:
    """Call before the process starts threads (it binds arenas not yet created). True when
    glibc took the limit; False where ``MALLOC_ARENA_MAX`` is set or there is no glibc."""
    return _mallopt("MALLOC_ARENA_MAX", _M_ARENA_MAX, arenas)


def map_large_buffers(threshold: int = LARGE_BUFFER_BYTES) -> bool:
    """Allocations of ``threshold`` bytes or more mapped on their own and returned to the
    system when freed, whatever was freed before (a fixed threshold turns off glibc's raising
    of it). True when glibc took it; False where ``MALLOC_MMAP_THRESHOLD_`` is set or there is
    no glibc."""
    return _mallopt("MALLOC_MMAP_THRESHOLD_", _M_MMAP_THRESHOLD, threshold)


def _mallopt(variable: str, option: int, value: int) -> bool:
    if variable in os.environ:
        return False
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6")
        return libc.mallopt(option, int(value)) == 1
    except (OSError, AttributeError):
        return False
