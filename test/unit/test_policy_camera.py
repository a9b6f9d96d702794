"""The observation's camera block (policy/observation.py): the middle row of an rgb8 or mono8
image in gray levels, averaged into bins; the image from a sensor_msgs/Image's fields. Pure
logic, no ROS, no core."""
import numpy as np
import pytest

from epuck_vrep_compat.policy import observation as ob

RNG = np.random.default_rng(2525)


def bt601_mono8(rgb):
    """The drivers' gray mode, written out pixel by pixel: round(0.299 R + 0.587 G + 0.114 B)."""
    rgb = np.asarray(rgb, float)
    return np.rint(0.299 * rgb[..., 0] + 0.587 * rgb[..., 1] + 0.114 * rgb[..., 2])


def test_bin_weights_share_every_pixel_once():
    w = ob.bin_weights(40, 16)                 # 2.5 pixels a bin
    assert w.shape == (40, 16)
    assert w.sum(axis=1) == pytest.approx(np.full(40, 0.4))  # each pixel counted once, in
    assert w.sum(axis=0) == pytest.approx(np.ones(16))       # bins of 2.5: each bin a mean
    assert w[:3, 0] == pytest.approx([0.4, 0.4, 0.2])        # pixel 2 half in bin 0, half in 1
    assert w[2, 1] == pytest.approx(0.2)
    exact = ob.bin_weights(160, 16)             # the drivers' 160 columns: 10 a bin
    assert np.array_equal(exact, np.kron(np.eye(16), np.full((10, 1), 0.1)))


def test_middle_row_of_odd_and_even_heights():
    """H odd: the middle row; H even: the mean of the two middle rows (the horizon lies
    between them); a mono8 level / 255."""
    for height, rows in ((1, [0]), (2, [0, 1]), (3, [1]), (40, [19, 20]), (41, [20])):
        image = RNG.integers(0, 256, (height, 32), dtype=np.uint8)
        expected = image[rows].astype(float).mean(axis=0).reshape(16, 2).mean(axis=1) / 255
        assert ob.camera_row(image, 16) == pytest.approx(expected, abs=1e-12)


def test_rgb8_gives_the_block_of_its_drivers_mono8():
    """An rgb8 image and its mono8 (the drivers' gray mode: BT.601 luma, rounded) give one
    block, bit for bit; pure colours land on the expected levels."""
    rgb = RNG.integers(0, 256, (40, 40, 3), dtype=np.uint8)
    mono = bt601_mono8(rgb).astype(np.uint8)
    assert np.array_equal(ob.camera_row(rgb), ob.camera_row(mono))
    pure = np.zeros((1, 3, 3), np.uint8)
    pure[0, 0, 0] = pure[0, 1, 1] = pure[0, 2, 2] = 255   # red, green, blue
    assert ob.camera_row(pure, 3) == pytest.approx(np.array([76, 150, 29]) / 255, abs=1e-12)
    white = np.full((2, 160, 3), 255, np.uint8)
    assert ob.camera_row(white) == pytest.approx(np.ones(16), abs=1e-12)


def test_camera_row_batches_over_leading_axes():
    images = RNG.integers(0, 256, (3, 2, 40, 40, 3), dtype=np.uint8)
    block = ob.camera_row(images, 8)
    assert block.shape == (3, 2, 8)
    assert np.array_equal(block[2, 1], ob.camera_row(images[2, 1], 8))
    assert ((block >= 0) & (block <= 1)).all()


def test_image_from_buffer_drops_row_padding_and_checks():
    pixels = RNG.integers(0, 256, (2, 5, 3), dtype=np.uint8)
    padded = np.zeros((2, 16), np.uint8)             # step 16 > 5 * 3
    padded[:, :15] = pixels.reshape(2, 15)
    image = ob.image_from_buffer(padded.tobytes(), 5, 2, 16, "rgb8")
    assert image.shape == (2, 5, 3) and np.array_equal(image, pixels)
    mono = ob.image_from_buffer(bytes(range(8)), 4, 2, 4, "mono8")
    assert mono.tolist() == [[0, 1, 2, 3], [4, 5, 6, 7]]
    with pytest.raises(ValueError, match="encoding"):
        ob.image_from_buffer(bytes(8), 4, 2, 4, "bgr8")
    with pytest.raises(ValueError, match="step"):
        ob.image_from_buffer(bytes(7), 4, 2, 4, "mono8")


def test_layout_and_build_with_the_camera_block():
    layout = ob.ObservationLayout(imu=True, neighbours=1, camera=True, camera_bins=4)
    assert layout.size == 8 + 6 + 3 + 4 == len(layout.names)
    assert layout.names[-4:] == ["cam0", "cam1", "cam2", "cam3"]
    low, high = layout.bounds()
    assert (low[-4:] == 0).all() and (high[-4:] == 1).all()
    assert ob.ObservationLayout.from_dict(layout.to_dict()) == layout
    old_file = {"imu": False, "neighbours": 0, "neighbour_range_m": 0.5,
                "names": [f"ir{k}" for k in range(8)]}          # a weights file of before
    assert ob.ObservationLayout.from_dict(old_file) == ob.ObservationLayout()
    ranges = np.full((2, 8), 0.05)
    camera = np.array([[0.1, 0.2, 0.3, 0.4], [0.5, 0.6, 0.7, 0.8]])
    obs = ob.build(layout, ranges, [0, 0, 9.81], [0, 0, 0], np.zeros(3), camera)
    assert obs.shape == (2, layout.size) and np.array_equal(obs[:, -4:], camera)
    with pytest.raises(ValueError, match="camera"):
        ob.build(layout, ranges, [0, 0, 9.81], [0, 0, 0], np.zeros(3))
    with pytest.raises(ValueError):
        ob.ObservationLayout(camera=True, camera_bins=0)
