"""V-REP's blob detection filter written out in Python as its source does it: breadth-first
8-connected labels in V-REP's scan order (bottom row first), each blob's boundary pixels, and
the coarse-to-fine search for the rotation of least bounding-box area over them.

The reference that test_cell_sensors.py holds _core.detect_blobs to, and the pure-Python
baseline of bench/cell_sensors.py. Slow: for small images.
"""
import math
from collections import deque

import numpy as np


def label(up):
    """Pixel lists [(x, y), ...] of the 8-connected blobs of a bottom-up mask, in scan order."""
    height, width = up.shape
    rows = up.tolist()
    seen = [[False] * width for _ in range(height)]
    blobs = []
    for y in range(height):
        for x in range(width):
            if not rows[y][x] or seen[y][x]:
                continue
            seen[y][x], queue, pixels = True, deque([(x, y)]), []
            while queue:
                px, py = queue.popleft()
                pixels.append((px, py))
                for ny in range(max(py - 1, 0), min(py + 2, height)):
                    for nx in range(max(px - 1, 0), min(px + 2, width)):
                        if rows[ny][nx] and not seen[ny][nx]:
                            seen[ny][nx] = True
                            queue.append((nx, ny))
            blobs.append(pixels)
    return blobs


def rectangle(points, width, height):
    """(orientation, x, y, width, height) of pixel centres (N, 2) x, y up, V-REP's search."""
    def box(a):
        c, s = math.cos(a), math.sin(a)
        tx, ty = points[:, 0] * c - points[:, 1] * s, points[:, 0] * s + points[:, 1] * c
        return (tx.max() - tx.min()) * (ty.max() - ty.min()), a, tx, ty

    best = min((box(math.pi / 8 * j) for j in range(4)), key=lambda b: b[0])
    step = math.pi / 8
    for _ in range(3):
        step /= 3
        centre = best[1]
        for j in (-2, -1, 1, 2):
            candidate = box(centre + step * j)
            best = candidate if candidate[0] < best[0] else best
    _, a, tx, ty = best
    cx, cy = (tx.max() + tx.min()) / 2, (ty.max() + ty.min()) / 2
    x = cx * math.cos(-a) - cy * math.sin(-a) + 0.5
    y = cx * math.sin(-a) + cy * math.cos(-a) + 0.5
    return (-a, x / width, y / height, (tx.max() - tx.min()) / width,
            (ty.max() - ty.min()) / height)


def vrep_blobs(mask, min_size=0.0):
    """Rows (size, orientation, x, y, width, height) of a top-down mask's blobs, largest first
    (ties in scan order) like _core.detect_blobs, float32 as V-REP's packet."""
    height, width = mask.shape
    up = np.asarray(mask, bool)[::-1]  # V-REP row y = height - 1 - row
    padded = np.pad(up, 1)
    rows = []
    for pixels in label(up):
        size = len(pixels) / (width * height)
        if size < min_size:
            continue
        edge = [(x, y) for x, y in pixels if not padded[y:y + 3, x:x + 3].all()]
        rows.append((size,) + rectangle(np.array(edge, float), width, height))
    rows.sort(key=lambda row: -row[0])  # stable: ties stay in scan order
    return np.array(rows, np.float32).reshape(-1, 6)
