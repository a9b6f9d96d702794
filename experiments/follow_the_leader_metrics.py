"""Experiment 3's own metric: how well ePuck1 keeps its gap behind ePuck0.

A user-defined metric of the experiment runner: it receives the run's context (the recorded
topics as numpy arrays) and returns numbers. The distance is between the robots' centres from
their ground truth (``/ePuckN/ground_truth``, recorded for the built-in metrics), at the
instants both have; the error is that distance less the follower's gap, after the approach.
"""
import numpy as np

GAP_M = 0.12          # the follow_the_leader node's default ~gap_m
APPROACH_S = 5.0      # the follower's first seconds are its approach, not its tracking


def gap_error(ctx):
    lead = ctx.series("/ePuck0/ground_truth")
    follow = ctx.series("/ePuck1/ground_truth")
    common, i, j = np.intersect1d(lead.t, follow.t, return_indices=True)
    dx = lead.field("pose.pose.position.x")[i] - follow.field("pose.pose.position.x")[j]
    dy = lead.field("pose.pose.position.y")[i] - follow.field("pose.pose.position.y")[j]
    error = np.hypot(dx, dy)[common >= APPROACH_S] - GAP_M
    return {"gap_error_mean_m": float(np.mean(np.abs(error))),
            "gap_error_rms_m": float(np.sqrt(np.mean(error ** 2))),
            "distance_max_m": float(np.max(error + GAP_M))}
