"""The cell's robot models: URDF file and base, and their V-REP names (the one table of those
is :mod:`epuck_vrep_compat.compat.cell_names`)."""
from dataclasses import dataclass
from pathlib import Path

from epuck_vrep_compat.compat import cell_names
from epuck_vrep_compat.paths import data_path


@dataclass(frozen=True)
class RobotModel:
    """A cell robot's model: URDF file, V-REP names (base link, joints in contract order)."""
    urdf_file: str
    names: cell_names.RobotNames
    fixed_base: bool     # the arms stand on the floor; the youBot's base is floating

    @property
    def base_link(self) -> str:
        return self.names.base_link

    @property
    def joints(self) -> tuple:
        return self.names.joints

    @property
    def urdf_path(self):
        return Path(data_path("models", self.urdf_file))


IRB140 = RobotModel("irb140.urdf", cell_names.IRB140, fixed_base=True)
COMAU_SMART_SIX = RobotModel("comau_smart_six.urdf", cell_names.COMAU_SMART_SIX, fixed_base=True)
YOUBOT = RobotModel("youbot.urdf", cell_names.YOUBOT, fixed_base=False)

CELL_ROBOTS = (IRB140, COMAU_SMART_SIX, YOUBOT)
