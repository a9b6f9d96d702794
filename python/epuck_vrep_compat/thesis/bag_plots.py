"""The thesis's plots of a recorded run, as PNG files (matplotlib's Agg canvas, no display):

- ``blob_camera_<k>.png`` (figure 5.10): the operator's blob track seen by camera k, x against
  y, from /vrep/Blob_Camera_k_X and /vrep/Blob_Camera_k_Y (std_msgs/Float32, published by the
  cameras' child scripts through the plugin); an X and a Y sample belong together when their
  receive times are within half a V-REP step (25 ms);
- ``<Robot>_joint_<n>.png`` (figures 5.11 to 5.24): joint n's absolute position x, y, z over
  time, from /<Robot>_PosOrAss; time is headerGiunto's stamp (the bag's receive time where the
  stamp is 0), in seconds from the topic's first message.
- ``ssm_<robot>.png``: a safety run's separation, S_p and speed scale (:mod:`ssm_plots`).
A topic the bag does not have is reported and its plots skipped.
"""
import os
from typing import Dict, List, Tuple

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from epuck_vrep_compat.compat.thesis_names import CAMERAS, ROBOTS
from epuck_vrep_compat.compat.topics import BLOB_TOPIC_FORMAT
from epuck_vrep_compat.thesis.ssm_plots import plot_ssm

BLOB_MATCH_TOLERANCE_S = 0.025      # half of V-REP's default 50 ms step


def match_by_time(tx, x, ty, y, tolerance_s: float = BLOB_MATCH_TOLERANCE_S):
    """Pairs (x_i, y_j) with y_j the sample nearest in time to x_i, within ``tolerance_s``."""
    tx, x, ty, y = (np.asarray(a, dtype=float) for a in (tx, x, ty, y))
    if len(tx) == 0 or len(ty) == 0:
        return np.empty(0), np.empty(0)
    order = np.argsort(ty)
    ty, y = ty[order], y[order]
    after = np.searchsorted(ty, tx)             # first y sample at or after each x sample
    left = np.clip(after - 1, 0, len(ty) - 1)
    right = np.clip(after, 0, len(ty) - 1)
    nearest = np.where(np.abs(ty[left] - tx) <= np.abs(ty[right] - tx), left, right)
    keep = np.abs(ty[nearest] - tx) <= tolerance_s
    return x[keep], y[nearest][keep]


def _float_series(bag, topic) -> Tuple[np.ndarray, np.ndarray]:
    """(receive times [s], values) of a std_msgs/Float32 topic."""
    times, values = [], []
    for _, msg, t in bag.read_messages(topics=[topic]):
        times.append(t.to_sec())
        values.append(msg.data)
    return np.array(times, dtype=float), np.array(values, dtype=float)


def joint_tracks(messages) -> Dict[int, Tuple[str, np.ndarray, np.ndarray]]:
    """{indice: (nome, times [s from the first sample], positions (N, 3))} of a sequence of
    (vett_posOrAssGiunto, receive time) pairs."""
    samples: Dict[int, List] = {}
    names: Dict[int, str] = {}
    for msg, receive_time in messages:
        for joint in msg.posizioneOrientamento:
            head = joint.headerGiunto
            stamp = head.header.stamp if not head.header.stamp.is_zero() else receive_time
            samples.setdefault(head.indice, []).append([stamp.to_sec()]
                                                       + list(joint.Posizione_Assoluta))
            names[head.indice] = head.nome
    if not samples:
        return {}
    start = min(rows[0][0] for rows in samples.values())
    tracks = {}
    for indice, rows in sorted(samples.items()):
        array = np.array(rows, dtype=float)
        tracks[indice] = (names[indice], array[:, 0] - start, array[:, 1:4])
    return tracks


def _save(fig: Figure, path: str) -> str:
    FigureCanvasAgg(fig)
    fig.savefig(path, dpi=100)
    return path


def plot_blob_track(x, y, camera: int, path: str) -> str:
    fig = Figure(figsize=(5, 4.5))
    ax = fig.add_subplot()
    ax.plot(x, y, ".-", markersize=3, linewidth=0.8)
    ax.set_title(f"Relative position of the operator with respect to Camera{camera}")
    ax.set_xlabel("blob x (image fraction)")
    ax.set_ylabel("blob y (image fraction)")
    ax.grid(True)
    return _save(fig, path)


def plot_joint_track(label: str, indice: int, nome: str, t, xyz, path: str) -> str:
    fig = Figure(figsize=(7, 4))
    ax = fig.add_subplot()
    for k, axis in enumerate("xyz"):
        ax.plot(t, xyz[:, k], label=axis)
    ax.set_title(f"{label} joint {indice + 1} ({nome}): absolute position")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("position [m]")
    ax.legend()
    ax.grid(True)
    return _save(fig, path)


def plot_all(bag, outdir: str) -> List[str]:
    """Every plot the bag has the topics for; returns report lines (written and skipped)."""
    topics = set(bag.get_type_and_topic_info().topics)
    report = []
    for camera in sorted(CAMERAS):
        blob_topics = [BLOB_TOPIC_FORMAT.format(camera=camera, axis=a) for a in "XY"]
        absent = [t for t in blob_topics if t not in topics]
        if absent:
            report.append(f"skipped blob_camera_{camera}.png: no {', '.join(absent)} in the bag")
            continue
        x, y = match_by_time(*_float_series(bag, blob_topics[0]),
                             *_float_series(bag, blob_topics[1]))
        report.append(plot_blob_track(x, y, camera, os.path.join(
            outdir, f"blob_camera_{camera}.png")))
    for label, robot in ROBOTS.items():
        topic = robot.poses_topic(absolute=True)
        if topic not in topics:
            report.append(f"skipped {label}_joint_*.png: no {topic} in the bag")
            continue
        tracks = joint_tracks((msg, t) for _, msg, t in bag.read_messages(topics=[topic]))
        for indice, (nome, t, xyz) in tracks.items():
            report.append(plot_joint_track(label, indice, nome, t, xyz, os.path.join(
                outdir, f"{label}_joint_{indice + 1}.png")))
    return report + plot_ssm(bag, topics, outdir)
