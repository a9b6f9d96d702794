"""epuck_vrep_compat: a ROS 1 drop-in for V-REP's e-puck model and legacy ROS plugin.

The compiled core (:mod:`epuck_vrep_compat._core`) holds the per-step work: the Bullet collision
world, the e-puck swarm (differential drive, IR cones, IMU, noise), the ray-cast camera and the
cell's sensors (ray proximity array, laser scanner, depth noise, blob detection).

Importing this package loads nothing compiled: client nodes (the thesis's nodes, the examples,
``bag_to_csv``) import only what they use. The core's names below are re-exported lazily, on
first use (PEP 562), so ``from epuck_vrep_compat import CollisionWorld`` still works.
"""
import importlib

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
    "TofSensorArray",
    "apply_range_noise",
    "detect_blobs",
]


def __getattr__(name):
    if name in __all__:
        value = getattr(importlib.import_module("epuck_vrep_compat._core"), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'epuck_vrep_compat' has no attribute '{name}'")
