"""The simulator's ROS names that every face and client node shares, defined once.

The simulator node must be named ``vrep`` so that everything lands under ``/vrep/`` as V-REP's
clients expect.
"""
NODE_NAME = "vrep"
NODE = "/" + NODE_NAME                  # the simulator node's resolved name
NODE_NAMESPACE = NODE + "/"             # its private namespace: services, streams, markers
TF_TOPIC = "/tf"
TF_STATIC_TOPIC = "/tf_static"          # latched: frames fixed to their parent
CLOCK_TOPIC = "/clock"
INFO_TOPIC = NODE_NAMESPACE + "info"    # vrep_common/VrepInfo, the legacy plugin's
# the simulator's own control (std_srvs/Empty)
PAUSE_SERVICE = NODE_NAMESPACE + "pause"
UNPAUSE_SERVICE = NODE_NAMESPACE + "unpause"
RESET_SERVICE = NODE_NAMESPACE + "reset"
REWIND_SERVICE = NODE_NAMESPACE + "rewind"     # ours: time back to 0, a new seed (experiments)
# A client node's own reset (std_srvs/Trigger, under its private namespace: ``~reset``): the node
# as launched, for the next run of an experiment's launch (docs/experiments.md)
NODE_RESET_SERVICE = "reset"

# Each cell robot's topics and description, ``robot`` its ROS name (cell_names.ros_robot_name).
JOINT_STATES_TOPIC = "/{robot}/joint_states"            # sensor_msgs/JointState, out
JOINT_COMMAND_TOPIC = "/{robot}/joint_command"          # sensor_msgs/JointState, in
BASE_CMD_VEL_TOPIC = "/{robot}/cmd_vel"                 # geometry_msgs/Twist, a mobile base's
ROBOT_DESCRIPTION_PARAM = "/{robot}/robot_description"  # its URDF, links named as TF frames
# The cell's laser scanner, under /vrep/ (the scene file's default; a scene may rename it).
CELL_LASER_TOPIC = "front_scan"

# The cell's safety interface (issue 13): a supervisor's speed override per robot, in; the
# operator-to-link separation from the simulator's collision world, a service of /vrep.
SPEED_SCALE_TOPIC = "/{robot}/speed_scale"              # std_msgs/Float64, 0..1
# std_msgs/Bool, latched, on change: the simulator holds the robot, its speed scale went stale
SAFETY_STOP_TOPIC = "/{robot}/safety_stop"
OPERATOR_SEPARATION_SERVICE = NODE_NAMESPACE + "operator_separation"
# The operator's blob, published by the ceiling cameras' child scripts through the plugin
# (thesis 5.1): the thesis's nodes and the operator tracker read it.
BLOB_TOPIC_FORMAT = NODE_NAMESPACE + "Blob_Camera_{camera}_{axis}"
# The Kinect's depth in metres (sensor_msgs/Image 32FC1), from the thesis's [/kinect] node.
KINECT_DEPTH_IMAGE_TOPIC = "/kinect/depth/image"
# What ssm_supervisor publishes per robot (std_msgs/Float64 unless said): separation,
# protective_separation, scale, operator_uncertainty, protective_stop (Bool), status (String).
SSM_TOPIC_FORMAT = "/ssm_supervisor/{robot}/{what}"
# each node's steps taken without something it waits for in lock-step (ros/common/late_steps.py)
LATE_STEPS_PARAM = "/experiment/late_steps"
