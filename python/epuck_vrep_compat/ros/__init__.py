"""ros layer of epuck_vrep_compat."""
