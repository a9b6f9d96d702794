"""epuck_vrep_compat: a ROS 1 drop-in for V-REP's e-puck model and legacy ROS plugin.

The compiled core (:mod:`epuck_vrep_compat._core`) holds the per-step work: the Bullet collision
world, the e-puck swarm (differential drive, IR cones, IMU, noise), the ray-cast camera and the
cell's sensors (ray proximity array, laser scanner, depth noise, blob detection).
"""
from epuck_vrep_compat._core import (  # noqa: F401  (re-exported API)
    GROUP_ALL,
    GROUP_DYNAMIC,
    GROUP_FLOOR,
    GROUP_ROBOT,
    GROUP_STATIC,
    CollisionWorld,
    ConeSensor,
    DepthNoise,
    EpuckModel,
    EpuckSwarm,
    LaserScanner,
    RayProximityArray,
    Rng,
    apply_range_noise,
    detect_blobs,
)

__all__ = [
    "GROUP_ALL",
    "GROUP_DYNAMIC",
    "GROUP_FLOOR",
    "GROUP_ROBOT",
    "GROUP_STATIC",
    "CollisionWorld",
    "ConeSensor",
    "DepthNoise",
    "EpuckModel",
    "EpuckSwarm",
    "LaserScanner",
    "RayProximityArray",
    "Rng",
    "apply_range_noise",
    "detect_blobs",
]
