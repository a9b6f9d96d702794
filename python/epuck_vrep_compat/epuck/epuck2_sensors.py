"""The e-puck2's sensors beyond the e-puck's (its driver's ``dist_sens``, ``mag_field``,
``battery``, ``floor``, ``microphone``), as model state read after each step like the swarm's.

A :class:`~epuck_vrep_compat.sim.extension.SimulationExtension`: after every step of the
e-pucks (:class:`~epuck_vrep_compat.epuck.swarm.EpuckRobots`) it fills one row per robot (rows
as their ``robot_names``):

* ``tof_m`` (N,): the VL53L0X time-of-flight range, ray cast in the C++ core
  (``TofSensorArray``, its own seeded noise per robot);
* ``mag_tesla`` (N, 3): a constant world field ``B`` seen in the body frame,
  ``R_z(yaw)^T B`` plus Gaussian noise of SD ``mag_stddev_tesla`` per axis;
* ``battery_v`` (N,): ``v_full - (v_full - v_empty) t / discharge_s``, held at ``v_empty``,
  ``t`` the simulated time since the robot appeared (or the last reset);
* ``floor`` (N, 3): the three ground sensors (left, centre, right, ahead of the wheels), each
  ``round(1000 · grey)`` of the floor under it, grey = mean of its RGB (white reads 1000,
  black 0; the real sensor's reflected infrared, calibrated to that span);
* ``mic`` (N, M): the configured sound level of each microphone (no acoustics are simulated).

Only the readings asked for (``readings``, the profile's extra topics) are computed; the others
stay empty (the e-puck 1 driver publishes the floor and microphones only).

The magnetometer's noise is counter-based: each draw is a hash of (its seed, robot number,
frame, axis) turned normal by Box–Muller, vectorised over the swarm; so a robot's noise depends
on nothing but its own number and the frame, the same seed gives the same run, and another robot
added or removed changes nothing. The time-of-flight noise has its own stream per robot in the
core. Both seeds come from the builder, derived from the simulation's by name.
"""
import math
from dataclasses import dataclass, field
from typing import Tuple

import numpy as np

from epuck_vrep_compat import TofSensorArray
from epuck_vrep_compat.geometry.fixed_order import libm
from epuck_vrep_compat.sim.extension import SimulationExtension
from epuck_vrep_compat.scene.floor_regions import floor_rgb

# ground sensors in the body frame (x forward, y left), metres: the ground module's three
# sensors in a row across the front, under the body
GROUND_SENSORS_M = np.array([[0.030, 0.010], [0.030, 0.0], [0.030, -0.010]])
READINGS = frozenset(("dist_sens", "mag_field", "battery", "floor", "microphone"))


@dataclass
class Epuck2Settings:
    """What the e-puck2's extra sensors read (parameters ``~epuck2/*``)."""

    tof_mount_m: Tuple[float, float, float] = (0.035, 0.0, 0.034)
    tof_pitch_rad: float = -0.21
    tof_stddev_m: float = 0.003
    tof_stddev_rel: float = 0.02
    mag_world_tesla: Tuple[float, float, float] = (2.2e-5, 0.0, -4.2e-5)  # north along +x
    mag_stddev_tesla: float = 1.0e-6
    battery_full_v: float = 4.2
    battery_empty_v: float = 3.4
    battery_discharge_s: float = 10800.0       # 3 h from full to empty
    mic_levels: Tuple[int, ...] = field(default_factory=lambda: (0, 0, 0, 0))


def _mix(x):
    """splitmix64's finaliser on uint64 arrays (wrapping arithmetic)."""
    x = (x ^ (x >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
    x = (x ^ (x >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    return x ^ (x >> np.uint64(31))


def hashed_normals(seed: int, robot_ids, frame: int, count: int) -> np.ndarray:
    """(N, count) standard normals, each a function of (seed, robot id, frame, column) only."""
    with np.errstate(over="ignore"):
        base = _mix(np.uint64(seed % 2 ** 64))
        key = _mix(base ^ _mix(np.asarray(robot_ids, dtype=np.uint64) + np.uint64(1)))
        key = _mix(key ^ np.uint64(frame % 2 ** 64))
        cols = np.arange(2 * count, dtype=np.uint64)
        bits = _mix(key[:, None] + cols[None, :] * np.uint64(0x9E3779B97F4A7C15))
    u = ((bits >> np.uint64(11)).astype(np.float64) + 1.0) * 2.0 ** -53   # (0, 1]
    u1, u2 = u[:, :count], u[:, count:]      # the C library's log and cos: any processor's
    return np.sqrt(-2.0 * libm(math.log, u1)) * libm(math.cos, 2.0 * np.pi * u2)


class Epuck2Sensors(SimulationExtension):
    """Computes the e-puck2's extra readings of every robot of ``epucks`` (the EpuckRobots)
    after each step; its noise streams are seeded with ``tof_seed`` and ``mag_seed``."""

    def __init__(self, epucks, settings: Epuck2Settings, tof_seed: int, mag_seed: int,
                 floor_regions=(), floor_base_rgb=(0.85, 0.85, 0.8), readings=READINGS):
        self.epucks = epucks
        self.sim = epucks.sim
        self.settings = settings
        self.tof_seed, self.mag_seed = int(tof_seed), int(mag_seed)
        self.readings = READINGS & frozenset(readings)
        self._regions = list(floor_regions)
        self._floor_base = np.asarray(floor_base_rgb, dtype=float)
        s = settings
        self._tof = None
        if "dist_sens" in self.readings:
            self._tof = TofSensorArray(np.asarray(s.tof_mount_m), s.tof_pitch_rad,
                                       stddev_m=s.tof_stddev_m, stddev_rel=s.tof_stddev_rel,
                                       seed=self.tof_seed)
        # robot (its noise stream id: never given twice, unlike a name) -> simulated time it
        # appeared (or the last reset)
        self._born_s = {}
        self.tof_m = np.zeros(0)
        self.mag_tesla = np.zeros((0, 3))
        self.battery_v = np.zeros(0)
        self.floor = np.zeros((0, 3), dtype=np.int64)
        self.mic = np.zeros((0, len(s.mic_levels)), dtype=np.int64)
        self.step(0.0)

    def step(self, dt: float) -> None:
        sim, epucks, s, wanted = self.sim, self.epucks, self.settings, self.readings
        swarm = epucks.swarm
        poses = np.asarray(swarm.poses, dtype=float).reshape(-1, 3)
        noise = epucks.noise.enabled
        if self._tof is not None:
            self.tof_m = self._tof.read(sim.world, poses, [int(h) for h in swarm.handles],
                                        list(swarm.stream_ids), noise)
        # the C library's sin/cos: numpy's own (SVML on AVX-512) depend on the processor and,
        # for a strided column, on where the result lies in memory (1 ulp apart)
        c, sn = libm(math.cos, poses[:, 2]), libm(math.sin, poses[:, 2])
        if "mag_field" in wanted:
            self.mag_tesla = self._magnetometer(c, sn, noise)
        if "battery" in wanted:
            self.battery_v = self._battery(list(swarm.stream_ids), sim.time_s)
        if "floor" in wanted:
            self.floor = self._floor(poses, c, sn)
        if "microphone" in wanted:
            self.mic = np.tile(np.asarray(s.mic_levels, dtype=np.int64), (len(poses), 1))

    def _magnetometer(self, c, sn, noise):
        s = self.settings
        bx, by, bz = s.mag_world_tesla
        mag = np.stack((c * bx + sn * by, -sn * bx + c * by, np.full_like(c, bz)), axis=1)
        if noise and s.mag_stddev_tesla > 0.0:
            ids = np.asarray(self.epucks.swarm.stream_ids, dtype=np.uint64)
            mag += s.mag_stddev_tesla * hashed_normals(self.mag_seed, ids, self.sim.frame, 3)
        return mag

    def _battery(self, robots, now_s):
        s = self.settings
        if len(self._born_s) > len(robots):                 # some went: forget them
            alive = set(robots)
            self._born_s = {r: t for r, t in self._born_s.items() if r in alive}
        born = np.array([self._born_s.setdefault(r, now_s) for r in robots])
        used = (now_s - born) / s.battery_discharge_s
        return np.maximum(s.battery_full_v - (s.battery_full_v - s.battery_empty_v) * used,
                          s.battery_empty_v)

    def _floor(self, poses, c, sn):
        gx, gy = GROUND_SENSORS_M[:, 0], GROUND_SENSORS_M[:, 1]
        x = poses[:, :1] + c[:, None] * gx - sn[:, None] * gy
        y = poses[:, 1:2] + sn[:, None] * gx + c[:, None] * gy
        rgb = floor_rgb(self._regions, self._floor_base, np.stack((x, y), axis=2).reshape(-1, 2))
        return np.rint(1000.0 * rgb.mean(axis=1)).astype(np.int64).reshape(-1, 3)

    def reset(self) -> None:
        if self._tof is not None:
            self._tof.reseed(self.tof_seed)
        self._born_s.clear()
        self.step(0.0)
