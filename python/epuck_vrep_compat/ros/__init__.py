"""The ROS layer: the simulator node ``/vrep`` and its faces. Imports run one way, downwards:

* bottom: ``common`` (throttled log, parameters; the client nodes use it too, so it loads
  rospy only; the names are :mod:`epuck_vrep_compat.compat`'s), ``transport`` (the step
  batch, pre-serialised layouts), ``messages.py`` (message builders several faces use),
  ``face.py`` (the protocol every face follows);
* faces, which never import each other: ``epuck`` (the e-puck topic profiles), ``vrep_plugin``
  (V-REP's legacy ROS plugin: info, services, streams), ``cell`` (the industrial cell);
* top: ``node`` (the simulator node: parameters, the step loop over the faces, master watch).
"""
