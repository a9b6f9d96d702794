"""The cell's devices: the components that give its registry objects behaviour (the arms in
pybullet, their joints, scripts, link collisions and mecanum base, the walking operator, the
ray proximity sensors, the laser, ceiling cameras and Kinect)."""
