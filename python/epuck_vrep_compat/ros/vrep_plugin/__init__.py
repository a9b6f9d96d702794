"""V-REP's legacy ROS plugin on our simulation: ``/vrep/info``, the simRos* services and the
streams enabled through them."""
