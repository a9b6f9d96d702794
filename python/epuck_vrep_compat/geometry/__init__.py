"""geometry layer of epuck_vrep_compat: pure geometry in numpy (no ROS, nothing compiled), for
the simulator and the client nodes alike.

:mod:`.transforms` quaternions, Euler angles, rotation matrices and pose composition;
:mod:`.urdf_kinematics` a URDF tree's forward kinematics; :mod:`.fixed_order` weighted sums
in one fixed order and the C library's functions element by element (the same bits on any
processor, alone and in a batch)."""
