"""Cell robots loaded while the simulation runs (simRosLoadModel of an IRB 140, a SMART SiX or a
youBot model file): a working URDF robot with its joints, sensors-free, no default script,
named as V-REP names a pasted copy when the name is taken: the base ``IRB140#0`` and every
joint and link with the same suffix (``IRB140_joint1#0``)."""
from collections import namedtuple

from epuck_vrep_compat.cell.devices.articulated import ArticulatedRobot
from epuck_vrep_compat.scene.cell_file import ArmSpec

LOADED_COLOR = (0.7, 0.7, 0.75)
LoadedRobot = namedtuple("LoadedRobot", "root")    # a cell robot loaded: its base object


def copy_name(registry, name):
    """(name, suffix): the name itself while it is free, else V-REP's ``name#k``, k the
    smallest free."""
    if registry.handle_of(name) < 0:
        return name, ""
    k = 0
    while registry.handle_of(f"{name}#{k}") >= 0:
        k += 1
    return f"{name}#{k}", f"#{k}"


def load_cell_robot(cell, model):
    """Builds the model file's robot into the cell; returns it (a :data:`LoadedRobot`)."""
    registry = cell.sim.registry
    name, suffix = copy_name(registry, model.name)
    spec = ArmSpec(name=name, urdf=model.urdf,
                   position_m=(model.position_m[0], model.position_m[1], model.height_m),
                   yaw_rad=model.yaw_rad, mobile=model.mobile, script="none",
                   color=LOADED_COLOR)
    arm = ArticulatedRobot(cell.client, spec, registry, suffix)
    cell.add_arm(arm)
    return LoadedRobot(arm.objects[arm.chain.root])
