"""The ROS nodes of the master thesis's industrial cell (chapter 4), clients of ``/vrep`` only.

Robot subset: the HUB [/robot] (:mod:`.hub`) publishes the robots' and joints' handles;
[/Comau], [/Irb], [/YouBot] (:mod:`.joint_names`) add the joints' names; [/N<Robot>_PosOrAss]
and [/N<Robot>_PosOrRel] (:mod:`.joint_poses`) publish every joint's pose. Sensor subset:
[/proxSensors] (:mod:`.prox_sensors`), [/telecamera_0], [/telecamera_1] (:mod:`.cameras`),
[/kinect] (:mod:`.kinect`). Names in :mod:`epuck_vrep_compat.compat.thesis_names`; shared
client code in :mod:`.vrep_client`; ``bag_to_csv`` in :mod:`.bag_export` and :mod:`.bag_plots`.
"""
