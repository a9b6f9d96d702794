"""What a learned or hand-written e-puck controller needs on both sides of the gap between
simulation and ROS, in plain numpy (no ROS, no core): the one observation builder
(``observation.py``), neighbours' range and bearing from poses (``neighbours.py``), the shipped
perceptron controller and its weights file (``controller.py``). The learning environments
(``learn/``) and ``policy_node`` (a ROS client) both import it, so a policy sees the same vector
in training and on the robot."""
