"""geometry layer of epuck_vrep_compat: pure geometry in numpy (no ROS, nothing compiled), for
the simulator and the client nodes alike.

:mod:`.transforms` quaternions, Euler angles, rotation matrices and pose composition;
:mod:`.urdf_kinematics` a URDF tree's forward kinematics."""
