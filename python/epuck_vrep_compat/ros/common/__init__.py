"""What the simulator node and the client nodes share: names, throttled logging, parameters.

Light on purpose: rospy only, never the simulation (client nodes import it)."""
