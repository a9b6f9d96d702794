"""devices layer of epuck_vrep_compat: the components that give registry objects behaviour
(wheel joints, proximity and vision sensors of the e-puck; the cell's arms, ray sensors,
cameras and walking operator)."""
