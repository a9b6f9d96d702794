"""V-REP's API semantics over our scene: handles, poses, joints, sensors, signals, simulation
state. ROS-free; the ``/vrep`` node (``epuck_vrep_compat.ros.vrep_*``) is a face on it."""
