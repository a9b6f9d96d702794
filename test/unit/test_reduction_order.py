"""Results that do not depend on the processor or on where the numbers sit in memory
(docs/testing.md, the last section): the camera row, the perceptron's forward pass, the
neighbours' block, the follow task's reward and the e-puck2's hashed noise give the same bits
for an input alone (contiguous, aligned) and for the same input misaligned (a view of a byte
buffer at an odd offset), strided (every other element), transposed or in Fortran order, or
as one row of a batch; and a child process whose numpy is limited to the baseline SIMD
(``NPY_DISABLE_CPU_FEATURES``) gives the same bits as this process with the machine's best
kernels. No ROS."""
import hashlib
import json
import math
import os
import struct
import subprocess
import sys

import numpy as np
import pytest

from epuck_vrep_compat.epuck.epuck2_sensors import hashed_normals
from epuck_vrep_compat.geometry.fixed_order import libm, weighted_sums
from epuck_vrep_compat.learn.tasks import make_task
from epuck_vrep_compat.policy import neighbours
from epuck_vrep_compat.policy import observation as ob
from epuck_vrep_compat.policy.controller import Perceptron
from epuck_vrep_compat.policy.observation import ObservationLayout


def bits(a) -> str:
    """The float64 bytes of ``a`` (C order), hashed: equal only if every bit is."""
    return hashlib.sha256(np.ascontiguousarray(a, dtype=np.float64).tobytes()).hexdigest()


def misaligned(a, offset=3):
    """``a``'s values in a view of a byte buffer starting ``offset`` bytes in: unaligned."""
    a = np.asarray(a)
    raw = np.zeros(a.nbytes + offset, np.uint8)
    view = np.frombuffer(raw.data, dtype=a.dtype, count=a.size, offset=offset).reshape(a.shape)
    view[...] = a
    assert a.itemsize == 1 or not view.flags.aligned
    return view


def every_other(a):
    """``a``'s values as every other element of a buffer twice as long (a strided view)."""
    a = np.asarray(a)
    wide = np.zeros(a.shape[:-1] + (2 * a.shape[-1],), a.dtype)
    wide[..., ::2] = a
    return wide[..., ::2]


def transposed(a):
    """``a``'s values in a transposed buffer (Fortran order for 2-D)."""
    return np.asarray(a).T.copy().T


def layouts(a):
    """(name, view) of ``a`` in every layout, the contiguous one first."""
    a = np.ascontiguousarray(a)
    return [("contiguous", a), ("misaligned", misaligned(a)), ("misaligned+5", misaligned(a, 5)),
            ("every other", every_other(a)), ("transposed", transposed(a)),
            ("fortran", np.asfortranarray(a))]


def assert_same_bits_in_every_layout(function, a):
    want = bits(function(np.ascontiguousarray(a)))
    for name, view in layouts(a):
        assert np.array_equal(view, a)
        assert bits(function(view)) == want, f"{name} layout gives other bits"


def rng():
    return np.random.default_rng(4141)


def perceptron():
    layout = ObservationLayout(imu=True, neighbours=2, camera=True, camera_bins=16)
    weights = rng().uniform(-3.0, 3.0, (2, layout.size))
    return Perceptron(weights, (0.3, -0.2), layout)


def observations(n=64):
    return rng().uniform(-1.0, 1.0, (n, perceptron().layout.size))


def poses(groups=4, per=6):
    p = rng().uniform(-0.4, 0.4, (groups * per, 3))
    p[:, 2] = rng().uniform(-math.pi, math.pi, groups * per)
    return p


def images():
    return rng().integers(0, 256, (3, 2, 40, 40, 3), dtype=np.uint8)


def test_camera_row_same_bits_alone_in_a_batch_and_in_every_layout():
    batch = images()
    block = ob.camera_row(batch, 16)
    for i in range(3):
        for j in range(2):
            assert bits(block[i, j]) == bits(ob.camera_row(np.array(batch[i, j]), 16))
    rgb = batch[1, 0]
    for name, view in layouts(rgb):       # the channel axis strided, transposed, Fortran
        assert bits(ob.camera_row(view, 16)) == bits(block[1, 0]), name
    mono = ob.gray_levels(rgb).astype(np.uint8)
    assert_same_bits_in_every_layout(lambda m: ob.camera_row(m, 16), mono)
    assert_same_bits_in_every_layout(lambda m: ob.camera_row(m, 7), mono)     # part pixels


def test_camera_row_is_the_exact_quotient():
    """Each bin is its integer sum of gray levels times overlaps, over 2 * 255 * width: one
    rounding, checked against Python's exact fractions."""
    from fractions import Fraction
    mono = rng().integers(0, 256, (3, 40), dtype=np.uint8)
    row = ob.camera_row(mono, 7)
    levels = [2 * int(v) for v in mono[1]]
    for k in range(7):
        total = sum(Fraction(levels[j]) * max(0, min((j + 1) * 7, (k + 1) * 40)
                                              - max(j * 7, k * 40)) for j in range(40))
        assert row[k] == float(total / (2 * 255 * 40))


def test_gray_levels_are_the_luma_written_out_for_a_million_colours():
    """Every red and green with every 16th blue (one image of 256 x 4096): the drivers' gray
    mode element by element, ``rint((0.299 R + 0.587 G) + 0.114 B)``, whatever numpy's
    kernel (a matrix product put about one colour in 12 000 on the other level here)."""
    r, g, b = np.meshgrid(np.arange(256.0), np.arange(256.0), np.arange(0.0, 256.0, 16.0),
                          indexing="ij")
    written_out = np.rint(0.299 * r + 0.587 * g + 0.114 * b).reshape(256, 4096)
    image = np.stack([r, g, b], axis=-1).astype(np.uint8).reshape(256, 4096, 3)
    assert bits(ob.gray_levels(image)) == bits(written_out)


def test_gray_levels_same_bits_in_a_batch_and_every_layout():
    batch = images()
    gray = ob.gray_levels(batch)
    assert bits(gray[2, 1]) == bits(ob.gray_levels(np.array(batch[2, 1])))
    assert_same_bits_in_every_layout(ob.gray_levels, batch[0, 0])


def test_perceptron_same_bits_alone_in_a_batch_and_in_every_layout():
    p, obs = perceptron(), observations()
    out = p(obs)
    for i in range(len(obs)):
        assert bits(out[i]) == bits(p(np.array(obs[i])))
    assert bits(p(obs.reshape(8, 8, -1)).reshape(64, 2)) == bits(out)    # leading axes
    assert_same_bits_in_every_layout(p, obs)
    assert np.allclose(out, np.tanh(obs @ p.weights.T + p.bias), rtol=0, atol=1e-12)


@pytest.mark.parametrize("size", [0, 1, 2, 3, 7, 8, 9, 16, 33])
def test_weighted_sums_every_length_alone_batched_and_in_every_layout(size):
    x = rng().uniform(-1.0, 1.0, (20, size))
    w = rng().uniform(-2.0, 2.0, (3, size))
    out = weighted_sums(x, w)
    assert out.shape == (20, 3)
    assert np.allclose(out, x @ w.T, rtol=0, atol=1e-12)
    for i in range(20):
        assert bits(out[i]) == bits(weighted_sums(np.array(x[i]), w))
    if size:
        assert_same_bits_in_every_layout(lambda v: weighted_sums(v, w), x)
        assert_same_bits_in_every_layout(lambda v: weighted_sums(x, v), w)


def test_neighbours_block_alone_equals_the_batch_in_every_layout():
    p = poses()
    out = neighbours.blocks(p, 3, 0.5, groups=4)
    for r in range(len(p)):
        group = r // 6
        others = np.delete(p[6 * group:6 * group + 6, :2], r % 6, axis=0)
        assert bits(out[r]) == bits(neighbours.block(p[r], others, 3, 0.5))
    assert_same_bits_in_every_layout(lambda v: neighbours.blocks(v, 3, 0.5, groups=4), p)


def test_libm_and_the_follow_reward_and_noise_in_every_layout():
    x = rng().uniform(-3.0, 3.0, (16, 5))
    for f in (math.tanh, math.exp, math.cos, math.sin):
        assert_same_bits_in_every_layout(lambda v, f=f: libm(f, v), x)
    assert_same_bits_in_every_layout(lambda v: libm(math.atan2, v, x), x)
    task = make_task("follow_leader", 3, False, False, 16)
    wheels, contact = np.zeros((4, 3, 2)), np.zeros((4, 3), bool)
    obs = np.zeros((4, 3, task.layout.size))
    rewards = task.rewards(wheels, 1.0, obs, poses(4, 3).reshape(4, 3, 3), contact)
    alone = task.rewards(wheels[2:3], 1.0, obs[2:3], poses(4, 3).reshape(4, 3, 3)[2:3],
                         contact[2:3])
    assert bits(rewards[2:3]) == bits(alone)
    ids = np.arange(7, dtype=np.uint64)
    noise = hashed_normals(11, ids, 5, 3)
    assert bits(noise[4:5]) == bits(hashed_normals(11, ids[4:5], 5, 3))


def test_the_cores_loops_give_the_bits_of_pythons_math():
    """libm's C++ loops (``epuck_vrep_compat._libm``) call the C library's functions that ``math`` calls:
    the same bits for every value ``math`` answers (ordinary, tiny, huge, signed zeros, near
    the poles of atan2), in any layout; where ``math`` raises (exp's overflow, log of 0, cos of
    inf) the loop gives the C library's inf or nan."""
    r = rng()
    x = np.concatenate([r.uniform(-10.0, 10.0, 4000), 1e3 * r.standard_normal(500),
                        [0.0, -0.0, 1e-310, -1e-310, 1e300, -1e300, 709.7, 710.0, -745.2,
                         math.pi / 2, -math.pi, np.inf, -np.inf, np.nan]])
    y = r.permutation(x)
    for f in (math.tanh, math.exp, math.log, math.cos, math.sin, math.atan2):
        args = (y, x) if f is math.atan2 else (np.abs(x) if f is math.log else x,)
        got = libm(f, *(every_other(a) for a in args))
        for k, values in enumerate(zip(*args)):
            try:
                want = f(*values)
            except (OverflowError, ValueError):
                assert f in (math.exp, math.log, math.cos, math.sin) and (
                    np.isinf(got[k]) or np.isnan(got[k])), (f.__name__, values, got[k])
                continue
            assert struct.pack("<d", want) == struct.pack("<d", got[k]), (f.__name__, values)
    assert libm(math.atan2, np.ones((2, 1)), np.arange(3.0)).shape == (2, 3)
    assert libm(math.tanh, np.zeros((0, 3))).shape == (0, 3)
    assert libm(math.tanh, 0.5) == math.tanh(0.5)
    assert libm(math.erf, [0.5, 1.0]).tolist() == [math.erf(0.5), math.erf(1.0)]   # no loop


# What the child computes, in this process and in one whose numpy has only the baseline SIMD.
RESULTS = {
    "camera_row": lambda: ob.camera_row(images(), 16),
    "camera_row_parts": lambda: ob.camera_row(images(), 7),
    "perceptron": lambda: perceptron()(observations()),
    "weighted_sums": lambda: weighted_sums(observations(), perceptron().weights),
    "neighbours": lambda: neighbours.blocks(poses(), 3, 0.5, groups=4),
    "follow_reward": lambda: make_task("follow_leader", 3, False, False, 16).rewards(
        np.zeros((8, 3, 2)), 1.0, np.zeros((8, 3, 11)), poses(8, 3).reshape(8, 3, 3),
        np.zeros((8, 3), bool)),
    "hashed_normals": lambda: hashed_normals(11, np.arange(50, dtype=np.uint64), 5, 3),
    "tanh_exp_cos_atan2": lambda: np.stack([libm(f, np.linspace(-3, 3, 1001)) for f in
                                            (math.tanh, math.exp, math.cos)]
                                           + [libm(math.atan2, np.linspace(-3, 3, 1001), 0.7)]),
}

CHILD = """
import json, sys
from numpy.core._multiarray_umath import __cpu_dispatch__, __cpu_features__
sys.path.insert(0, {here!r})
import test_reduction_order as t
on = [f for f in __cpu_dispatch__ if __cpu_features__.get(f)]
print(json.dumps({{"features_on": on,
                  "bits": {{name: t.bits(make()) for name, make in t.RESULTS.items()}}}}))
"""


def beyond_baseline():
    """The SIMD extensions numpy dispatches to on this machine beyond its baseline (only
    names of the dispatch set: numpy refuses to disable another)."""
    from numpy.core._multiarray_umath import __cpu_dispatch__, __cpu_features__
    return [f for f in __cpu_dispatch__ if __cpu_features__.get(f)]


def test_baseline_simd_gives_the_bits_of_the_best_kernels():
    disabled = beyond_baseline()
    env = dict(os.environ, NPY_DISABLE_CPU_FEATURES=" ".join(disabled))
    code = CHILD.format(here=os.path.dirname(os.path.abspath(__file__)))
    done = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                          text=True, timeout=120, check=False)
    assert done.returncode == 0, done.stderr[-2000:]
    child = json.loads(done.stdout.strip().splitlines()[-1])
    assert child["features_on"] == [], f"still on with {disabled} disabled: {child}"
    here = {name: bits(make()) for name, make in RESULTS.items()}
    different = sorted(name for name in here if child["bits"][name] != here[name])
    assert not different, (f"other bits with numpy's SIMD limited to the baseline "
                           f"({len(disabled)} extensions off: {' '.join(disabled)}): "
                           f"{different}")
