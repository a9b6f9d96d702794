"""Messages of any type as numeric columns: what a run's recording keeps of each topic.

Every numeric field is a column named by its path (``pose.pose.position.x``, ``range``,
``linear_acceleration.z``); fixed-size numeric arrays of at most ``MAX_ARRAY`` elements give
one column per element (``position.0``); longer or variable-length arrays, strings and
covariances are left out (a user who needs them records a bag). A message's time is its
``header.stamp`` when it has one that is not zero, else the simulated time it arrived at.
"""
import numpy as np

from epuck_vrep_compat.experiment import metrics

NUMERIC = {"bool", "byte", "char", "int8", "uint8", "int16", "uint16", "int32", "uint32",
           "int64", "uint64", "float32", "float64"}
TIMES = {"time", "duration"}
MAX_ARRAY = 9


def _fields(cls, prefix=()):
    """(column name, path of attribute names and indices) of every numeric field."""
    out = []
    for name, kind in zip(cls.__slots__, cls._slot_types):
        path = prefix + (name,)
        base, _, size = kind.partition("[")
        if not size:
            if base in NUMERIC or base in TIMES:
                out.append((".".join(map(str, path)), path, base in TIMES))
            elif "/" in base or base == "Header" or base == "std_msgs/Header":
                sub = getattr(cls(), name).__class__
                out += _fields(sub, path)
            continue
        size = size.rstrip("]")
        if base in NUMERIC and size and int(size) <= MAX_ARRAY and \
                not name.endswith("covariance"):        # Imu's are 9: left out all the same
            for i in range(int(size)):
                out.append((".".join(map(str, path + (i,))), path + (i,), False))
    return out


def _get(msg, path):
    for p in path:
        msg = msg[p] if isinstance(p, int) else getattr(msg, p)
    return msg


class Columns:
    """The columns of one topic, grown message by message (not thread-safe: the probe
    holds its lock)."""

    def __init__(self, type_name, cls):
        self.type_name = type_name
        self.fields = _fields(cls)
        self.has_stamp = "header" in cls.__slots__
        self.t = []
        self.rows = []

    def add(self, msg, now_s):
        t = now_s
        if self.has_stamp:
            stamp = msg.header.stamp
            if stamp.secs or stamp.nsecs:
                t = stamp.to_sec()
        self.t.append(t)
        row = []
        for _name, path, is_time in self.fields:
            v = _get(msg, path)
            row.append(v.to_sec() if is_time else float(v))
        self.rows.append(row)

    def series(self):
        """The recording's ``TopicSeries``, sorted by time."""
        t = np.asarray(self.t, dtype=float)
        data = np.asarray(self.rows, dtype=float).reshape(len(self.rows), len(self.fields))
        order = np.argsort(t, kind="stable")
        return metrics.TopicSeries(type=self.type_name, t=t[order],
                                   fields={name: data[order, j].copy()
                                           for j, (name, _p, _) in enumerate(self.fields)})
