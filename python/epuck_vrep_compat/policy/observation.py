"""The observation vector of a controller, built from readings in the units the ROS topics
carry them, the same for the three topic profiles and for the learning environments.

Layout (:class:`ObservationLayout`; every block in this order, each value float64):

* ``ir0..ir7`` (always): each proximity sensor's activation
  ``clip((0.05 - range_m) / (0.05 - 0.005), 0, 1)``: 0 when nothing is within 5 cm, 1 at 5 mm
  or nearer. 5 mm is the drivers' ``min_range`` (the ``vrep`` profile's is 1.5 mm) and 5 cm
  every profile's ``max_range``, so a ``sensor_msgs/Range`` of any profile, clipped to its own
  limits, and the core's reading in metres give the same activation.
* ``accel_x, accel_y, accel_z, gyro_x, gyro_y, gyro_z`` (``imu=True``): the body-frame specific
  force in units of g (9.81 m/s²: +1 on z at rest, as every profile publishes it) and the
  angular velocity in units of 5 rad/s (the e-puck turns at most 4.7 rad/s in place); each
  clipped to [-4, 4]. The ``epuck_driver`` profile (the e-puck 1) has no gyroscope: its three
  gyro values are 0 there.
* ``nbK_near, nbK_cos, nbK_sin`` for K < ``neighbours``: the K-th nearest other robot within
  ``neighbour_range_m`` (centre to centre), nearest first: ``1 - distance / neighbour_range_m``
  and the cosine and sine of its bearing in the robot's frame (0 ahead, + to the left); all
  three 0 for a slot with no robot in range.
* ``cam0..camK-1`` for K = ``camera_bins`` (``camera=True``, default K = 16): the camera row,
  the middle row of the robot's camera image (the mean of the two middle rows when the height
  is even: the rows at the horizon) as gray levels in [0, 1], averaged into K bins of equal
  width, ``cam0`` at the image's left edge (column 0: the robot's left). A gray level is a
  mono8 pixel / 255; an rgb8 pixel is first made mono8 as the drivers' gray mode makes it
  (ITU-R BT.601 luma ``0.299 R + 0.587 G + 0.114 B``, rounded), so an rgb8 and a mono8 image
  of one scene give the same block. A bin covering part of a pixel counts that part.
  :func:`camera_row` makes the block from an image (:func:`image_from_buffer` from a
  ``sensor_msgs/Image``'s fields).
"""
from dataclasses import asdict, dataclass
from typing import List, Optional

import numpy as np

IR_COUNT = 8
IR_MAX_RANGE_M = 0.05            # every profile's max_range: nothing seen
IR_MIN_RANGE_M = 0.005           # the drivers' min_range: full activation from here in
ACCEL_UNIT_M_S2 = 9.81
GYRO_UNIT_RAD_S = 5.0
IMU_CLIP = 4.0
IMU_NAMES = ("accel_x", "accel_y", "accel_z", "gyro_x", "gyro_y", "gyro_z")
CAMERA_BINS = 16
LUMA_BT601 = (0.299, 0.587, 0.114)
ENCODING_CHANNELS = {"rgb8": 3, "mono8": 1}


@dataclass(frozen=True)
class ObservationLayout:
    """Which blocks an observation holds (see the module's docstring for each value)."""

    imu: bool = False
    neighbours: int = 0
    neighbour_range_m: float = 0.5
    camera: bool = False
    camera_bins: int = CAMERA_BINS

    def __post_init__(self):
        if self.neighbours < 0 or not self.neighbour_range_m > 0.0:
            raise ValueError(f"neighbours must be >= 0 and neighbour_range_m > 0, got "
                             f"{self.neighbours}, {self.neighbour_range_m}")
        if self.camera_bins < 1:
            raise ValueError(f"camera_bins must be >= 1, got {self.camera_bins}")

    @property
    def names(self) -> List[str]:
        """The name of every value, in order."""
        names = [f"ir{k}" for k in range(IR_COUNT)]
        if self.imu:
            names += list(IMU_NAMES)
        for k in range(self.neighbours):
            names += [f"nb{k}_near", f"nb{k}_cos", f"nb{k}_sin"]
        if self.camera:
            names += [f"cam{k}" for k in range(self.camera_bins)]
        return names

    @property
    def size(self) -> int:
        return (IR_COUNT + (len(IMU_NAMES) if self.imu else 0) + 3 * self.neighbours
                + (self.camera_bins if self.camera else 0))

    def bounds(self):
        """(low, high) of every value: for a Box space."""
        low = np.zeros(self.size)
        high = np.ones(self.size)
        if self.imu:
            low[IR_COUNT:IR_COUNT + 6], high[IR_COUNT:IR_COUNT + 6] = -IMU_CLIP, IMU_CLIP
        start = IR_COUNT + (6 if self.imu else 0)
        for k in range(self.neighbours):
            low[start + 3 * k + 1:start + 3 * k + 3] = -1.0
        return low, high

    def to_dict(self) -> dict:
        return dict(asdict(self), names=self.names)

    @classmethod
    def from_dict(cls, data: dict) -> "ObservationLayout":
        layout = cls(imu=bool(data.get("imu", False)), neighbours=int(data.get("neighbours", 0)),
                     neighbour_range_m=float(data.get("neighbour_range_m", 0.5)),
                     camera=bool(data.get("camera", False)),
                     camera_bins=int(data.get("camera_bins", CAMERA_BINS)))
        if "names" in data and list(data["names"]) != layout.names:
            raise ValueError(f"observation names {list(data['names'])} do not match the "
                             f"layout's {layout.names}")
        return layout


def ir_activation(ranges_m) -> np.ndarray:
    """(..., 8) ranges [m] -> activations in [0, 1] (non-finite: nothing seen, 0)."""
    r = np.asarray(ranges_m, dtype=float)
    r = np.where(np.isfinite(r), r, IR_MAX_RANGE_M)
    return np.clip((IR_MAX_RANGE_M - r) / (IR_MAX_RANGE_M - IR_MIN_RANGE_M), 0.0, 1.0)


def image_from_buffer(data, width: int, height: int, step: int, encoding: str) -> np.ndarray:
    """The pixels of a ``sensor_msgs/Image`` (its ``data``, ``width``, ``height``, ``step``,
    ``encoding``: rgb8 or mono8) as uint8 (H, W, 3) or (H, W); ValueError otherwise."""
    if encoding not in ENCODING_CHANNELS:
        raise ValueError(f"camera encoding must be one of {sorted(ENCODING_CHANNELS)}, got "
                         f"{encoding!r}")
    channels = ENCODING_CHANNELS[encoding]
    raw = np.frombuffer(bytes(data), dtype=np.uint8)
    if width < 1 or height < 1 or step < width * channels or raw.size < step * height:
        raise ValueError(f"a {width}x{height} {encoding} image needs rows of at least "
                         f"{width * channels} bytes, got step {step} and {raw.size} bytes")
    pixels = raw[:step * height].reshape(height, step)[:, :width * channels]
    return pixels.reshape(height, width, 3) if channels == 3 else pixels.copy()


def gray_levels(image) -> np.ndarray:
    """mono8 (..., H, W) or rgb8 (..., H, W, 3) uint8 images -> their mono8 levels (..., H, W)
    as float: an rgb8 pixel's rounded BT.601 luma, as the drivers' gray mode makes it, written
    out ``(0.299 R + 0.587 G) + 0.114 B`` element by element (a matrix product's order, and so
    its rounding at a half, would follow numpy's kernel: the processor and the layout)."""
    image = np.asarray(image)
    if image.ndim >= 3 and image.shape[-1] == 3:
        (kr, kg, kb), rgb = LUMA_BT601, image.astype(float)
        return np.rint(kr * rgb[..., 0] + kg * rgb[..., 1] + kb * rgb[..., 2]).clip(0, 255)
    return image.astype(float)


def bin_overlaps(width: int, bins: int) -> np.ndarray:
    """(width, bins) integers: pixel column j's overlap with bin k in units of 1 / bins of a
    pixel (column j is [j bins, (j + 1) bins), bin k [k width, (k + 1) width) in those units);
    every bin's column sums to ``width``."""
    column = np.arange(width, dtype=np.int64)[:, None] * bins
    start = np.arange(bins, dtype=np.int64)[None, :] * width
    return np.clip(np.minimum(column + bins, start + width) - np.maximum(column, start), 0, None)


def bin_weights(width: int, bins: int) -> np.ndarray:
    """(width, bins): the share of pixel column j in bin k (bins of equal width, each column
    the interval [j, j + 1)); every column of the matrix sums to 1."""
    return bin_overlaps(width, bins) / width


def camera_row(image, bins: int = CAMERA_BINS) -> np.ndarray:
    """The camera block (..., bins) in [0, 1] of images (..., H, W, 3) rgb8 or (..., H, W)
    mono8 (a batch: leading axes; rgb8 needs its last axis of 3): the middle row (the two
    middle rows' mean for an even H) in gray levels / 255, averaged into ``bins`` bins.

    Exact: each bin is an integer sum (the gray levels of the middle rows, each weighted by
    its integer overlap, :func:`bin_overlaps`) divided once, so a value is the same bits for
    an image alone and in a batch, on any processor."""
    gray = gray_levels(image).astype(np.int64)
    height, width = gray.shape[-2:]
    rows = gray[..., (height - 1) // 2, :] + gray[..., height // 2, :]   # an odd H: twice
    return (rows @ bin_overlaps(width, bins)) / (2 * 255 * width)      # integers: exact


def build(layout: ObservationLayout, ranges_m, accel_m_s2=None, gyro_rad_s=None,
          neighbours: Optional[np.ndarray] = None, camera: Optional[np.ndarray] = None
          ) -> np.ndarray:
    """The observation (..., layout.size) from the readings of one robot (or a batch):
    ``ranges_m`` (..., 8); with ``layout.imu`` ``accel_m_s2`` and ``gyro_rad_s`` (..., 3);
    with ``layout.neighbours`` the block ``neighbours`` (..., 3 K) from
    :func:`epuck_vrep_compat.policy.neighbours.block`; with ``layout.camera`` the block
    ``camera`` (..., camera_bins) from :func:`camera_row`."""
    parts = [ir_activation(ranges_m)]
    lead = parts[0].shape[:-1]
    if layout.imu:
        if accel_m_s2 is None or gyro_rad_s is None:
            raise ValueError("this layout has the IMU block: accel and gyro are needed")
        imu = np.concatenate([np.asarray(accel_m_s2, float) / ACCEL_UNIT_M_S2,
                              np.asarray(gyro_rad_s, float) / GYRO_UNIT_RAD_S], axis=-1)
        parts.append(np.clip(np.broadcast_to(imu, lead + (6,)), -IMU_CLIP, IMU_CLIP))
    if layout.neighbours:
        if neighbours is None:
            raise ValueError("this layout has the neighbours block: neighbours are needed")
        parts.append(np.broadcast_to(np.asarray(neighbours, float),
                                     lead + (3 * layout.neighbours,)))
    if layout.camera:
        if camera is None:
            raise ValueError("this layout has the camera block: the camera row is needed")
        parts.append(np.broadcast_to(np.asarray(camera, float), lead + (layout.camera_bins,)))
    return np.concatenate(parts, axis=-1)
