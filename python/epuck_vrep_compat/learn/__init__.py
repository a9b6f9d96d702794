"""Learning on the simulation: Gymnasium and PettingZoo environments on the core's batched
worlds (a face on the simulation, like the ROS faces, that imports nothing of ROS). Importing
this package registers the Gymnasium ids:

* ``EpuckObstacleAvoidance-v0`` (Floreano and Mondada's fitness), ``EpuckAggregation-v0``,
  ``EpuckFollowLeader-v0``: ``gymnasium.make(id)`` gives the single-robot ``EpuckEnv``,
  ``gymnasium.make_vec(id, num_envs=B)`` the batched ``EpuckVectorEnv``. Their keyword
  arguments (the registration's defaults, REGISTERED_KWARGS, and ``noise``, ``robots``,
  ``episode_steps``, ``camera_spec``, ``render_mode``) are ``EpuckEnv``'s.

The swarm: ``epuck_vrep_compat.learn.parallel.EpuckParallelEnv(task=...)``, a PettingZoo
``ParallelEnv``; batched over B worlds, ``parallel_vector.EpuckParallelVectorEnv`` (dicts of
arrays or arrays (B, A, ...)) and its Gymnasium view of B x A agents,
``flat_vector.EpuckFlatVectorEnv``. Observations come from the policy package's builder, which ``policy_node``
uses on the ROS topics (docs/learning.md).
"""
import gymnasium

from epuck_vrep_compat.policy.observation import CAMERA_BINS

ENVIRONMENTS = {
    "EpuckObstacleAvoidance-v0": "obstacle_avoidance",
    "EpuckAggregation-v0": "aggregation",
    "EpuckFollowLeader-v0": "follow_leader",
}
# the observation's optional blocks, off by default: gymnasium.make(id, imu=True, camera=True)
REGISTERED_KWARGS = {"imu": False, "camera": False, "camera_bins": CAMERA_BINS}

for _id, _task in ENVIRONMENTS.items():
    if _id not in gymnasium.registry:
        gymnasium.register(id=_id, entry_point="epuck_vrep_compat.learn.env:EpuckEnv",
                           vector_entry_point="epuck_vrep_compat.learn.vector:EpuckVectorEnv",
                           kwargs=dict(REGISTERED_KWARGS, task=_task))
