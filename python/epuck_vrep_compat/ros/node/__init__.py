"""The simulator node ``/vrep``: parameters, the step loop over the faces, the master watch."""
