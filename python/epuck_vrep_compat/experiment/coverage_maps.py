"""Coverage maps of a cell's sensor layout (``safety_bench coverage``): where on the floor the
operator tracker sees the operator, and how well.

The operator walks a lawnmower path over the whole floor (``experiments/safety_ssm/
layouts/*_coverage.yaml``) in one run of ``experiments/safety_ssm/coverage.yaml``, recorded to
a bag: his true position and how many ceiling cameras see him (``/safety_bench/operator``:
x, y and z, from ``bench_truth``) and the tracker's error (``/safety_bench/truth``'s z). Per cell of a grid (``CELL_M``): the mean error,
and the mean number of cameras that see him there. The PNG draws both beside the layout (the
robots, the laser, the Kinect and the cameras, from the scene file).
"""
import math
import os

import numpy as np
import yaml

CELL_M = 0.4                    # the lawnmower's rows are 0.4 m apart
TRUTH, OPERATOR = "/safety_bench/truth", "/safety_bench/operator"
# a visited cell counts as seen when the mean number of cameras seeing him there (over his
# steps in it) is at least this many: e.g. one camera in half the steps, or two in a quarter
SEEN_MEAN_CAMERAS = 0.5


def read_bag(path):
    """(x, y, error, cameras) per step of a coverage run's bag (see the module's docstring)."""
    import rosbag                      # Debian's ROS; only this reader needs it
    truth, where = {}, []               # matched by stamp, in whole nanoseconds
    with rosbag.Bag(path) as bag:
        for topic, msg, _stamp in bag.read_messages(topics=[TRUTH, OPERATOR]):
            stamp = msg.header.stamp.to_nsec()
            if topic == TRUTH:
                truth[stamp] = msg.vector.z
            else:
                where.append((stamp, msg.point.x, msg.point.y, msg.point.z))
    where = [w for w in where if w[0] in truth]
    x, y, cameras = (np.array([w[i] for w in where]) for i in (1, 2, 3))
    return x, y, np.array([truth[w[0]] for w in where]), cameras


def grid(x, y, error, cameras, size_m, cell_m=CELL_M):
    """(mean error, mean cameras) per cell, arrays (rows along y, columns along x), NaN where
    he never was; the floor centred on the origin, ``size_m`` = (x, y)."""
    nx, ny = (int(math.ceil(s / cell_m)) for s in size_m)
    ix = np.clip(((np.asarray(x) + size_m[0] / 2) / cell_m).astype(int), 0, nx - 1)
    iy = np.clip(((np.asarray(y) + size_m[1] / 2) / cell_m).astype(int), 0, ny - 1)
    count = np.zeros((ny, nx))
    np.add.at(count, (iy, ix), 1.0)
    error = np.asarray(error, dtype=float)
    known = np.isfinite(error)
    err_sum, err_n = np.zeros((ny, nx)), np.zeros((ny, nx))
    np.add.at(err_sum, (iy[known], ix[known]), error[known])
    np.add.at(err_n, (iy[known], ix[known]), 1.0)
    cam_sum = np.zeros((ny, nx))
    np.add.at(cam_sum, (iy, ix), np.asarray(cameras, dtype=float))
    with np.errstate(invalid="ignore", divide="ignore"):
        return err_sum / np.where(err_n > 0, err_n, np.nan), \
            cam_sum / np.where(count > 0, count, np.nan)


def summary(error_grid, camera_grid):
    """The layout's figures: the fraction of visited cells seen (a mean of at least
    ``SEEN_MEAN_CAMERAS`` cameras there), and the mean and worst of the cells' mean errors."""
    visited = np.isfinite(camera_grid)
    errors = error_grid[np.isfinite(error_grid)]
    seen = camera_grid[visited] >= SEEN_MEAN_CAMERAS
    return {"seen_fraction": float(np.mean(seen)) if visited.any() else math.nan,
            "error_mean_m": float(np.mean(errors)) if errors.size else math.nan,
            "error_max_m": float(np.max(errors)) if errors.size else math.nan}


def layout(scene):
    """{kind: [(x, y)]} of the scene's robots and sensors, for the map."""
    cell = scene.get("cell", {})
    out = {"robots": [tuple(r["position_m"][:2]) for r in cell.get("robots", [])]}
    if "laser" in cell:
        out["laser"] = [tuple(cell["laser"]["position_m"][:2])]
    if "kinect" in cell:
        out["kinect"] = [tuple(cell["kinect"]["position_m"][:2])]
    out["cameras"] = [(c["matrix"][3], c["matrix"][7]) for c in cell.get("cameras", [])
                      if "matrix" in c]
    return out


def draw(path, scene_path, error_grid, camera_grid, title):
    """The PNG: the error map and the camera map side by side, the layout on both."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    with open(scene_path) as f:
        scene = yaml.safe_load(f)
    sx, sy = scene["arena"]["size_m"][:2]
    extent = (-sx / 2, sx / 2, -sy / 2, sy / 2)
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.6))
    figures = summary(error_grid, camera_grid)
    panels = ((error_grid, "tracker error [m]", "viridis", 0.0, 0.5),
              (camera_grid, "ceiling cameras seeing him", "magma", 0.0, 2.0))
    marks = {"robots": ("s", "white"), "laser": ("^", "red"), "kinect": ("D", "cyan"),
             "cameras": ("o", "orange")}
    for ax, (values, label, cmap, lo, hi) in zip(axes, panels):
        image = ax.imshow(values, origin="lower", extent=extent, cmap=cmap, vmin=lo, vmax=hi)
        fig.colorbar(image, ax=ax, label=label)
        for kind, points in layout(scene).items():
            if points:
                xs, ys = zip(*points)
                ax.scatter(xs, ys, marker=marks[kind][0], c=marks[kind][1],
                           edgecolors="black", s=60, label=kind)
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
    axes[0].legend(loc="upper left", fontsize=7)
    fig.suptitle(f"{title}: seen (>= {SEEN_MEAN_CAMERAS:g} cameras on average) in "
                 f"{figures['seen_fraction']:.0%} of the floor, "
                 f"error mean {figures['error_mean_m']:.3f} m, worst cell "
                 f"{figures['error_max_m']:.2f} m")
    fig.tight_layout()
    os.makedirs(os.path.dirname(path) or ".", exist_ok=True)
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return figures
