# Used by catkin_python_setup(); not for pip.
from setuptools import setup
from catkin_pkg.python_setup import generate_distutils_setup

setup(**generate_distutils_setup(
    packages=[
        "epuck_vrep_compat",
        "epuck_vrep_compat.builder",
        "epuck_vrep_compat.compat",
        "epuck_vrep_compat.geometry",
        "epuck_vrep_compat.policy",
        "epuck_vrep_compat.learn",
        "epuck_vrep_compat.cell",
        "epuck_vrep_compat.cell.devices",
        "epuck_vrep_compat.devices",
        "epuck_vrep_compat.epuck",
        "epuck_vrep_compat.scene",
        "epuck_vrep_compat.sim",
        "epuck_vrep_compat.ros",
        "epuck_vrep_compat.ros.common",
        "epuck_vrep_compat.ros.transport",
        "epuck_vrep_compat.ros.epuck",
        "epuck_vrep_compat.ros.epuck.drivers",
        "epuck_vrep_compat.ros.vrep_plugin",
        "epuck_vrep_compat.ros.cell",
        "epuck_vrep_compat.ros.node",
        "epuck_vrep_compat.vrep",
        "epuck_vrep_compat.nodes",
        "epuck_vrep_compat.thesis",
        "epuck_vrep_compat.fidelity",
        "epuck_vrep_compat.experiment",
    ],
    package_dir={"": "python"},
))
