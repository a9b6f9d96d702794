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

# The cell's safety interface (issue 13): a supervisor's speed override per robot, in; the
# operator-to-link separation from the simulator's collision world, a service of /vrep.
SPEED_SCALE_TOPIC = "/{robot}/speed_scale"              # std_msgs/Float64, 0..1
OPERATOR_SEPARATION_SERVICE = NODE_NAMESPACE + "operator_separation"
# The operator's blob, published by the ceiling cameras' child scripts through the plugin
# (thesis 5.1): the thesis's nodes and the operator tracker read it.
BLOB_TOPIC_FORMAT = NODE_NAMESPACE + "Blob_Camera_{camera}_{axis}"
# The Kinect's depth in metres (sensor_msgs/Image 32FC1), from the thesis's [/kinect] node.
KINECT_DEPTH_IMAGE_TOPIC = "/kinect/depth/image"
# What ssm_supervisor publishes per robot (std_msgs/Float64 unless said): separation,
# protective_separation, scale, operator_uncertainty, protective_stop (Bool), status (String).
SSM_TOPIC_FORMAT = "/ssm_supervisor/{robot}/{what}"
