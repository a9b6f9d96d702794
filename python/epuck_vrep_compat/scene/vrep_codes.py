"""The one table of V-REP codes the scene itself uses (v_repConst.h of V-REP 3.3.0): object
types, handle constants, joint and proximity sensor codes, and the compatibility names (the
world frame). The registry, the devices and :mod:`epuck_vrep_compat.vrep.constants` take them
from here; pure constants, so the client nodes import them without loading anything else.
"""
# Object types (sim_object_*_type)
OBJECT_SHAPE = 0
OBJECT_JOINT = 1
OBJECT_GRAPH = 2
OBJECT_CAMERA = 3
OBJECT_DUMMY = 4
OBJECT_PROXIMITY_SENSOR = 5
OBJECT_PATH = 8
OBJECT_VISION_SENSOR = 9
OBJECT_VOLUME = 10
OBJECT_MILL = 11
OBJECT_FORCE_SENSOR = 12
OBJECT_LIGHT = 13
OBJECT_MIRROR = 14
OBJECT_TYPE_END = 108
APPOBJ_OBJECT = 109            # sim_appobj_object_type: "all scene objects"
APPOBJ_COLLECTION = 115

# Handle constants (sim_handle_*)
HANDLE_ALL = -2
HANDLE_ALL_EXCEPT_EXPLICIT = -3
HANDLE_SELF = -4
HANDLE_MAIN_SCRIPT = -5
HANDLE_TREE = -6
HANDLE_CHAIN = -7
HANDLE_SINGLE = -8
HANDLE_DEFAULT = -9
HANDLE_ALL_EXCEPT_SELF = -10
HANDLE_PARENT = -11
HANDLE_SCENE = -12
WORLD = -1

# Joint subtypes and modes (dataType 16)
JOINT_REVOLUTE = 10
JOINT_PRISMATIC = 11
JOINT_SPHERICAL = 12
JOINTMODE_PASSIVE = 0
JOINTMODE_MOTION = 1
JOINTMODE_IK = 2
JOINTMODE_IKDEPENDENT = 3
JOINTMODE_DEPENDENT = 4
JOINTMODE_FORCE = 5
JOINTMODE_HYBRID_FLAG = 65536     # dataType 16: added to the mode when option bit 0 is set

# Proximity sensor subtypes
PROXSENSOR_PYRAMID = 30
PROXSENSOR_CYLINDER = 31
PROXSENSOR_DISC = 32
PROXSENSOR_CONE = 33
PROXSENSOR_RAY = 34

# The world's frame id in ROS messages (tf parents, absolute poses)
WORLD_FRAME = "world"
