"""What the simulator node and the client nodes share beyond names (those are in
:mod:`epuck_vrep_compat.compat`): throttled logging, parameters.

Light on purpose: rospy only, never the simulation (client nodes import it)."""
