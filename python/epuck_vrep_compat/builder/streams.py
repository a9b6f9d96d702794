"""Every random stream of a simulation, derived by name from its one seed.

``stream_seed(seed, name)`` is the first 8 bytes, read little-endian, of the SHA-256 digest of
the seed as 8 little-endian bytes (modulo 2^64) followed by the stream's name in UTF-8: stable
across runs, machines and Python versions (unlike ``hash()``), and independent for every name,
so that a stream added later changes none of the others. The names:

* ``cell/laser``: the cell's laser scanner's range noise (the core's ``LaserScanner``);
* ``cell/kinect``: the Kinect's depth noise (the core's ``DepthNoise``);
* ``epuck2/tof``: the e-puck2's time-of-flight noise, one stream per robot in the core
  (``TofSensorArray``);
* ``epuck2/magnetometer``: the e-puck2's magnetometer noise, counter-based
  (:func:`~epuck_vrep_compat.epuck.epuck2_sensors.hashed_normals`).

The e-puck swarm's own streams (IR, IMU, wheel slip) are the core's, seeded with the seed itself
(``EpuckSwarm``, one stream per robot): unchanged, as the paper's figures depend on them.
"""
import hashlib

CELL_LASER = "cell/laser"
CELL_KINECT = "cell/kinect"
EPUCK2_TOF = "epuck2/tof"
EPUCK2_MAGNETOMETER = "epuck2/magnetometer"


def stream_seed(seed: int, name: str) -> int:
    """The seed (0 <= s < 2^64) of the random stream ``name`` of a simulation seeded ``seed``."""
    key = (int(seed) % 2 ** 64).to_bytes(8, "little") + name.encode("utf-8")
    return int.from_bytes(hashlib.sha256(key).digest()[:8], "little")
