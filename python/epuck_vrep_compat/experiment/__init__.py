"""Experiments at scale: many runs of unchanged ROS code against the simulator, on Dask.

A client of the simulator like the thesis's nodes: it launches the simulator and the user's
code with roslaunch, one isolated master per run, records the run through ROS topics, and
turns every run into a row of a results table. Nothing of the simulator's insides is loaded.
"""
