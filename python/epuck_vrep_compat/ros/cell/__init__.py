"""The industrial cell's face: joints, laser, TF, blob streams and rviz."""
