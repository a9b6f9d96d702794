"""What the simulator node and the client nodes share beyond names (those are in
:mod:`epuck_vrep_compat.compat`): throttled logging, parameters; and, for the simulator's
faces only, the lock-step wait for each step's answers (:mod:`lockstep`).

Light on purpose: rospy only, never the simulation (client nodes import it)."""
