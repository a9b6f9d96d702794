"""``/vrep/rewind`` (``epuck_vrep_compat/Rewind``): the simulation back to its start as if
launched again with another seed, so that one launch serves several runs (the experiment
runner's ``runs_per_launch``, docs/experiments.md).

Paused at time 0 (frame 0: ``/clock`` goes back, unlike a stop or ``~reset``, so it is for
clients that start again with it), every extension reset as a stop does, the noise streams
seeded from the new seed by name as the builder seeds them, the operator walking the walk of
the new walk seed (``~operator_walk_seed``'s), the lock-step's counts and the safety topics as
built (once the answers to the last step have come, or the lock-step's time-out has passed:
one still on its way would count against the next run). Refused (``success`` false, why in
``message``, nothing changed): a negative seed, a walk seed without a cell operator, a new
seed with the e-puck2's sensors (their streams are not reseeded). Call it while no step is under way: paused, or synchronous with no trigger pending.
"""
import rospy

from epuck_vrep_compat.builder.build import rewind_simulation
from epuck_vrep_compat.compat.topics import REWIND_SERVICE
from epuck_vrep_compat.srv import Rewind, RewindResponse


class RewindService:
    """The service, for the node's simulation, its control, its faces' lock-step (or None) and
    the cell's face (or None)."""

    def __init__(self, sim, control, lockstep, cell_face):
        self._sim, self._control, self._lockstep, self._cell_face = (sim, control, lockstep,
                                                                     cell_face)
        self._service = rospy.Service(REWIND_SERVICE, Rewind, self._on_rewind)

    def _on_rewind(self, req):
        refusal = None
        if not 0 <= req.seed < 2 ** 63:
            refusal = f"seed {req.seed} must be a non-negative integer"
        elif req.operator_walk_seed < -1:
            refusal = f"operator_walk_seed {req.operator_walk_seed} must be >= 0 (or -1: keep)"
        if refusal:
            rospy.logwarn("rewind refused: %s", refusal)
            return RewindResponse(False, refusal)
        walk_seed = req.operator_walk_seed if req.operator_walk_seed >= 0 else None
        if self._lockstep is not None:
            self._lockstep.settle()     # the last step's answers in before the counts restart
        with self._sim.lock:
            try:
                rewind_simulation(self._sim, req.seed, walk_seed)
            except ValueError as e:
                rospy.logwarn("rewind refused: %s", e)
                return RewindResponse(False, str(e))
            self._control.rewind()
            if self._lockstep is not None:
                self._lockstep.restart()
            if self._cell_face is not None:
                self._cell_face.restart()
        rospy.loginfo("simulation rewound to t=0 with seed %d%s; paused", req.seed,
                      f", operator walk seed {req.operator_walk_seed}"
                      if req.operator_walk_seed >= 0 else "")
        return RewindResponse(True, "")
