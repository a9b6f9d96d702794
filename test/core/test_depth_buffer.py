"""V-REP's depth buffer in the core and the depth images rendered or noised in place: each bit
for bit what the numpy and allocating paths they replace give."""
import numpy as np
import pytest
from conftest import GREY, IDENTITY

from epuck_vrep_compat import _core

NEAR, FAR = 0.5, 5.0


def numpy_depth_buffer(depth, near, far):
    """The former path (vrep/devices.py): float64, in place, clipped, then float32."""
    normalised = depth[::-1].astype(np.float64)
    normalised -= near
    normalised /= far - near
    return np.clip(normalised, 0.0, 1.0, out=np.empty(normalised.shape, np.float32))


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_depth_buffer_equals_numpy_bit_for_bit(seed):
    rng = np.random.default_rng(seed)
    depth = rng.uniform(-1.0, 7.0, (48, 64)).astype(np.float32)
    depth[rng.random(depth.shape) < 0.1] = np.inf
    depth[rng.random(depth.shape) < 0.05] = NEAR
    depth[rng.random(depth.shape) < 0.05] = FAR
    depth[0, :3] = (np.nan, -np.inf, np.float32(NEAR) + np.float32(1e-7))
    for near, far in ((NEAR, FAR), (0.01, 3.5), (0.0, 1.0)):
        got = _core.vrep_depth_buffer(depth, near, far)
        want = numpy_depth_buffer(depth, near, far)
        assert got.dtype == np.float32 and got.shape == depth.shape
        assert got.tobytes() == want.tobytes()


def test_depth_buffer_rows_bottom_first_and_bad_arguments():
    depth = np.array([[1.0, 2.0], [3.0, 4.0], [5.0, 6.0]], np.float32)
    got = _core.vrep_depth_buffer(depth, 1.0, 6.0)
    np.testing.assert_array_equal(got, np.float32([[0.8, 1.0], [0.4, 0.6], [0.0, 0.2]]))
    for near, far in ((2.0, 1.0), (1.0, 1.0), (np.nan, 1.0), (0.0, np.inf)):
        with pytest.raises(ValueError, match="near_m < far_m"):
            _core.vrep_depth_buffer(depth, near, far)
    with pytest.raises(ValueError, match="2-D"):
        _core.vrep_depth_buffer(np.zeros(4, np.float32), NEAR, FAR)


def test_depth_noise_in_place_equals_its_copy():
    rng = np.random.default_rng(7)
    depth = rng.uniform(0.0, 6.0, (30, 40)).astype(np.float32)
    depth[rng.random(depth.shape) < 0.2] = np.inf
    copy = _core.DepthNoise(seed=3).apply(depth, NEAR, FAR)
    in_place = depth.copy()
    returned = _core.DepthNoise(seed=3).apply(in_place, NEAR, FAR, out=in_place)
    assert returned.ctypes.data == in_place.ctypes.data
    assert in_place.tobytes() == copy.tobytes()
    other = np.empty_like(depth)
    _core.DepthNoise(seed=3).apply(depth, NEAR, FAR, out=other)
    assert other.tobytes() == copy.tobytes()


@pytest.mark.parametrize("out", [np.empty((30, 41), np.float32), np.empty((30, 40)),
                                 np.empty((40, 30), np.float32).T, [[0.0] * 40] * 30])
def test_outputs_of_the_wrong_kind_are_refused(world, out):
    depth = np.ones((30, 40), np.float32)
    with pytest.raises(ValueError, match="out must be a writable C-contiguous float32"):
        _core.DepthNoise(seed=3).apply(depth, NEAR, FAR, out=out)
    with pytest.raises(ValueError, match="out must be a writable C-contiguous float32"):
        world.render((0, 0, 0), IDENTITY, 40, 30, 0.8, NEAR, FAR, rgb=False, depth_out=out)


def test_render_into_a_kept_array_equals_a_new_one(world):
    world.add_box(1, (0.2, 0.3, 0.4), (2.0, 0.1, 0.0), IDENTITY, GREY)
    world.add_sphere(2, 0.3, (3.0, -0.5, 0.2), IDENTITY, GREY)
    view = ((0, 0, 0), IDENTITY, 64, 48, 0.8, NEAR, FAR)
    new = world.render(*view, rgb=False)[1]
    kept = np.full((48, 64), -1.0, np.float32)
    returned = world.render(*view, rgb=False, depth_out=kept)[1]
    assert returned.ctypes.data == kept.ctypes.data
    assert kept.tobytes() == new.tobytes()
    rgb, depth = world.render(*view, depth_out=kept)
    assert depth.tobytes() == new.tobytes() and rgb.shape == (48, 64, 3)
