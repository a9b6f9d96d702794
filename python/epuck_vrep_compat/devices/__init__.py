"""devices layer of epuck_vrep_compat: what gives registry objects behaviour, shared by every
robot family: the components' interface and vision sensor (:mod:`.components`). A family's own
devices are in its package (:mod:`epuck_vrep_compat.epuck`,
:mod:`epuck_vrep_compat.cell.devices`)."""
