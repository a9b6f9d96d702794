"""scene layer of epuck_vrep_compat: scene and model files, their checks, the object registry,
placement, the e-puck model and the cell robots' models."""
