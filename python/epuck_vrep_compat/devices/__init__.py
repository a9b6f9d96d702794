"""devices layer of epuck_vrep_compat: the components that give registry objects behaviour
(wheel joints, proximity and vision sensors of the e-puck). The cell's own devices are in
:mod:`epuck_vrep_compat.cell.devices`."""
