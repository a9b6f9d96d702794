"""``/vrep/rewind`` (``epuck_vrep_compat/Rewind``): the simulation back to its start as if
launched again with another seed, so that one launch serves several runs (the experiment
runner's ``runs_per_launch``, docs/experiments.md).

Paused at time 0 (frame 0: ``/clock`` goes back, unlike a stop or ``~reset``, so it is for
clients that start again with it), every extension reset as a stop does, the noise streams
seeded from the new seed by name as the builder seeds them, the operator walking the walk of
the new walk seed (``~operator_walk_seed``'s), the lock-step's counts and the safety topics as
built. Refused (``success`` false, why in ``message``, nothing changed): a negative seed, a walk
seed without a cell operator, a new seed with the e-puck2's sensors (their streams are not
reseeded). Call it while no step is under way: paused, or synchronous with no trigger pending.
"""
import rospy

from epuck_vrep_compat.builder.streams import CELL_KINECT, CELL_LASER, stream_seed
from epuck_vrep_compat.compat.topics import REWIND_SERVICE
from epuck_vrep_compat.srv import Rewind, RewindResponse


class RewindService:
    """The service of ``node`` (a :class:`~epuck_vrep_compat.ros.node.simulator_node.
    SimulatorNode`)."""

    def __init__(self, node):
        self._node = node
        self._service = rospy.Service(REWIND_SERVICE, Rewind, self._on_rewind)

    def _refusal(self, req):
        sim = self._node.sim
        if not 0 <= req.seed < 2 ** 63:
            return f"seed {req.seed} must be a non-negative integer"
        if req.operator_walk_seed < -1:
            return f"operator_walk_seed {req.operator_walk_seed} must be >= 0 (or -1: keep)"
        if req.operator_walk_seed >= 0 and (sim.cell is None or sim.cell.operator is None):
            return "operator_walk_seed: the scene has no cell operator"
        if sim.epuck2 is not None and req.seed != sim.seed:
            return "a new seed with the e-puck2's sensors (their streams are not reseeded)"
        return None

    def _on_rewind(self, req):
        refusal = self._refusal(req)
        if refusal:
            rospy.logwarn("rewind refused: %s", refusal)
            return RewindResponse(False, refusal)
        node = self._node
        sim = node.sim
        node.control.rewind()           # no step starts from here on
        with sim.lock:
            sim.seed = sim.epucks.seed = int(req.seed)
            if sim.cell is not None:
                sim.cell.laser_seed = stream_seed(req.seed, CELL_LASER)
                sim.cell.kinect_seed = stream_seed(req.seed, CELL_KINECT)
                if req.operator_walk_seed >= 0:
                    sim.cell.operator.rewalk(req.operator_walk_seed)
            sim.rewind()
            if node.lockstep is not None:
                node.lockstep.restart()
            if node.cell is not None:
                node.cell.restart()
        rospy.loginfo("simulation rewound to t=0 with seed %d%s; paused", req.seed,
                      f", operator walk seed {req.operator_walk_seed}"
                      if req.operator_walk_seed >= 0 else "")
        return RewindResponse(True, "")
