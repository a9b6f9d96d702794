"""Lock-step with a speed-and-separation supervisor (``~lockstep``): the simulator waits for
the supervisor's answer to step k before it takes step k+1, so that a safety run's outcome does
not depend on how fast the machine is (V-REP's synchronous mode, with the supervisor as the
client that triggers).

An answer is a ``/<robot>/speed_scale`` message from every watched robot (the watchdog's
robots: ``~speed_scale_robots``, every robot when empty); the simulator applies it at the next
step. Before the first step it waits for one scale from each (a supervisor in lock-step sends a
latched one when it is ready: the handshake). The supervisor answers every step once, in order
(:mod:`ssm_pacing`). The matching of answers to steps, the timeout of a dead supervisor and
the surplus scales are :class:`~epuck_vrep_compat.ros.common.lockstep.StepLockstep`'s.
"""
from epuck_vrep_compat.ros.common.lockstep import StepLockstep


class ScaleLockstep(StepLockstep):
    """Matches each watched robot's speed scales to the steps they answer, and waits for them."""

    def __init__(self, robots, timeout_s: float, connected=None):
        """``robots``: a callable giving the watched robots' names now; ``connected``: whether
        a robot's supervisor is still connected."""
        super().__init__(robots, timeout_s, "speed scale", handshake=True, connected=connected)
