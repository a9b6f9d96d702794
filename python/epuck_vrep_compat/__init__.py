"""epuck_vrep_compat: a ROS 1 drop-in for V-REP's e-puck model and legacy ROS plugin.

The compiled core (:mod:`epuck_vrep_compat._core`) holds the per-step work: the Bullet collision
world, the e-puck swarm (differential drive, IR cones, IMU, noise) and the ray-cast camera.
"""
from epuck_vrep_compat._core import (  # noqa: F401  (re-exported API)
    GROUP_ALL,
    GROUP_DYNAMIC,
    GROUP_FLOOR,
    GROUP_ROBOT,
    GROUP_STATIC,
    CollisionWorld,
    ConeSensor,
    EpuckModel,
    EpuckSwarm,
    Rng,
    apply_range_noise,
)

__all__ = [
    "GROUP_ALL",
    "GROUP_DYNAMIC",
    "GROUP_FLOOR",
    "GROUP_ROBOT",
    "GROUP_STATIC",
    "CollisionWorld",
    "ConeSensor",
    "EpuckModel",
    "EpuckSwarm",
    "Rng",
    "apply_range_noise",
]
