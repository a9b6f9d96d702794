"""What a run recorded and the numbers an experiment computes from it.

A run's recording is a ``Recording``: topic name (absolute) → :class:`TopicSeries`, one column a
numeric message field. The probe node writes it with :func:`save_recording`, the runner reads it
with :func:`load_recording`. A metric spec is ``{"metric": NAME, **options}``; :func:`compute`
turns a list of them and a :class:`RunContext` into one flat row ``{column: float}``.

Missing data (a topic or field not recorded, no message in the window, no robot) never raises:
that metric's columns are NaN and a warning saying why is appended to ``warnings`` when the
caller passes a list, else logged. A user-defined metric that raises anything is treated alike.
A malformed spec raises ValueError naming the option (:func:`validate_metric`, before any run).

Every built-in metric takes ``prefix`` (default ""), prepended to its columns, so that one
metric can be asked twice (two robots' IMU) without a clash; :func:`columns` checks for clashes.
Units: metres, seconds of simulated time (as stamped), m/s².
"""
import dataclasses
import logging
import math
import re
from typing import Callable, Dict, List, Mapping, Optional

import numpy as np

from epuck_vrep_compat.experiment.metrics_builtin import BUILTIN, CUSTOM, REQUIRED, series

FORMAT = "epuck_vrep_compat.recording/1"
TYPE_KEY = "@type"              # <topic>|@type: no message field path starts with "@"
_GROUND_TRUTH = re.compile(r"^/(?P<ns>.+)/ground_truth$")
_LOG = logging.getLogger(__name__)


@dataclasses.dataclass
class TopicSeries:
    """One topic's messages as columns: the ROS type (``nav_msgs/Odometry``), the stamps ``t``
    [s of simulated time, sorted] and ``fields``, each numeric message field by its flattened
    path (``pose.pose.position.x``, ``range``) with one float64 value per message, in the
    message's own units (SI)."""

    type: str
    t: np.ndarray
    fields: Dict[str, np.ndarray] = dataclasses.field(default_factory=dict)

    def __post_init__(self):
        self.t = np.asarray(self.t, dtype=np.float64).reshape(-1)
        self.fields = {k: np.asarray(v, dtype=np.float64).reshape(-1)
                       for k, v in self.fields.items()}
        for name, values in self.fields.items():
            if name == "t" or name.startswith("@") or "|" in name:
                raise ValueError(f"field name {name!r} is reserved by the recording format")
            if values.shape != self.t.shape:
                raise ValueError(f"field {name!r} has {values.size} values for {self.t.size} "
                                 "stamps")
        if np.any(np.diff(self.t) < 0):
            raise ValueError("stamps t must be sorted")

    def field(self, name: str) -> np.ndarray:
        """The values of one field; KeyError listing the fields there are."""
        if name not in self.fields:
            raise KeyError(f"a {self.type} series has no field {name!r}; it has: "
                           f"{', '.join(sorted(self.fields)) or 'none'}")
        return self.fields[name]


Recording = Dict[str, TopicSeries]


def save_recording(path: str, rec: Recording) -> None:
    """Writes a recording to one ``.npz`` file at exactly ``path``: ``<topic>|t``,
    ``<topic>|<field>`` and ``<topic>|@type`` arrays, no pickles."""
    arrays = {"format": np.array(FORMAT)}
    for topic, s in rec.items():
        if "|" in topic:
            raise ValueError(f"topic name {topic!r} holds '|'")
        arrays[f"{topic}|{TYPE_KEY}"] = np.array(s.type)
        arrays[f"{topic}|t"] = s.t
        arrays.update((f"{topic}|{name}", v) for name, v in s.fields.items())
    with open(path, "wb") as f:
        np.savez_compressed(f, **arrays)


def load_recording(path: str) -> Recording:
    """Reads what :func:`save_recording` wrote, bit for bit; ValueError for another file."""
    with np.load(path, allow_pickle=False) as data:
        if "format" not in data.files or str(data["format"]) != FORMAT:
            raise ValueError(f"{path} is not a recording ({FORMAT})")
        parts = {}
        for key in data.files:
            topic, sep, name = key.partition("|")
            if sep:
                parts.setdefault(topic, {})[name] = data[key]
    return {topic: TopicSeries(str(p.pop(TYPE_KEY)), p.pop("t"), p)
            for topic, p in sorted(parts.items())}


def robots_in(recording: Recording) -> List[str]:
    """The namespaces (no slashes at the ends) with a ``/<ns>/ground_truth`` topic, sorted."""
    return sorted(m.group("ns") for topic in recording for m in [_GROUND_TRUTH.match(topic)] if m)


@dataclasses.dataclass
class RunContext:
    """What a metric may look at about one finished run: its recording, its robots'
    namespaces (from the recording's ground truths when not given), the parsed scene file,
    the run's length [s of simulated time], parameter values, seed and bag."""

    recording: Recording
    robots: Optional[List[str]] = None
    world: dict = dataclasses.field(default_factory=dict)
    duration_s: float = math.nan
    params: dict = dataclasses.field(default_factory=dict)
    seed: int = 0
    bag_path: Optional[str] = None

    def __post_init__(self):
        if self.robots is None:
            self.robots = robots_in(self.recording)
        self.world = self.world or {}

    def series(self, topic: str) -> TopicSeries:
        """A recorded topic (for user-defined metrics); KeyError listing the recorded ones."""
        return series(self, topic)


def _checked(spec, custom_names=()):
    """(metric name, its table entry, its options checked and defaulted) or ValueError."""
    if not isinstance(spec, dict) or not isinstance(spec.get("metric"), str):
        raise ValueError(f"a metric spec must be a mapping with 'metric': one of "
                         f"{', '.join(sorted(BUILTIN))} or a user-defined metric, got {spec!r}")
    name = spec["metric"]
    is_custom = spec.get("custom") is True or name in custom_names
    if is_custom and name in BUILTIN:
        raise ValueError(f"metric {name!r}: a user-defined metric cannot take a built-in's name")
    if not is_custom and name not in BUILTIN:
        raise ValueError(f"unknown metric {name!r}; the built-in metrics are "
                         f"{', '.join(sorted(BUILTIN))}")
    entry = CUSTOM if is_custom else BUILTIN[name]
    options = {}
    for key, value in spec.items():
        if key == "metric":
            continue
        if key not in entry.options:
            raise ValueError(f"metric {name!r}: unknown option {key!r}; its options are "
                             f"{', '.join(sorted(entry.options))}")
        try:
            options[key] = entry.options[key][0](value)
        except ValueError as e:
            raise ValueError(f"metric {name!r}: option {key!r} {e}") from None
    for key, (_check, default) in entry.options.items():
        if key not in options:
            if default is REQUIRED:
                raise ValueError(f"metric {name!r}: option {key!r} is required")
            options[key] = default
    return name, entry, options


def validate_metric(spec: dict, custom: Optional[Mapping] = None) -> None:
    """Raises ValueError naming the metric and the option when ``spec`` is unusable: an unknown
    metric or option, a missing required option, a value of the wrong kind or range. A spec
    with ``custom: true`` or whose name is a key of ``custom`` is a user-defined metric."""
    _checked(spec, custom or ())


def topics_needed(metric_specs: List[dict]) -> List[str]:
    """The topic names or glob patterns (``/*/ground_truth``) the metrics read, sorted."""
    found = set()
    for spec in metric_specs:
        _name, entry, options = _checked(spec)
        found.update(entry.topics(options))
    return sorted(found)


def columns(metric_specs: List[dict]) -> List[str]:
    """The columns the metrics produce, in order (a user-defined metric's: its name, though it
    may return others); ValueError when two metrics would write one column."""
    seen = {}
    for i, spec in enumerate(metric_specs):
        name, entry, options = _checked(spec)
        for column in (entry.columns(options) if entry is not CUSTOM else [name]):
            column = options["prefix"] + column
            if column in seen:
                raise ValueError(f"metrics[{i}] ({name}) and metrics[{seen[column]}] both "
                                 f"write column {column!r}: give one a prefix")
            seen[column] = i
    return list(seen)


def compute(metric_specs: List[dict], ctx: RunContext,
            custom: Optional[Mapping[str, Callable]] = None,
            warnings: Optional[List[str]] = None) -> Dict[str, float]:
    """One run's metrics, ``{column: float}`` in the specs' order. ``custom`` maps a
    user-defined metric's name to ``f(ctx) -> float | {column: float}``. A metric whose data is
    missing (or a user's metric that raises) gives NaN columns and a warning, appended to
    ``warnings`` when given, else logged; a malformed spec raises ValueError."""
    custom = custom or {}
    row = {}
    for spec in metric_specs:
        name, entry, options = _checked(spec, custom)
        # a user's function may fail in any way; a built-in only for want of data
        caught = Exception if entry is CUSTOM else (LookupError, ValueError)
        try:
            raw = _custom(name, custom, ctx) if entry is CUSTOM else entry.compute(ctx, options)
            values = {column: float(value) for column, value in raw.items()}
        except caught as e:
            names = [name] if entry is CUSTOM else entry.columns(options)
            values = {c: math.nan for c in names}
            _warn(warnings, f"metric {name}: {type(e).__name__}: {e}")
        for column, value in values.items():
            column = options["prefix"] + column
            if column in row:
                _warn(warnings, f"metric {name}: column {column} already written; kept the first")
                continue
            row[column] = value
    return row


def _custom(name, custom, ctx):
    if name not in custom:
        raise LookupError(f"no function given for the user-defined metric {name!r}")
    value = custom[name](ctx)
    return dict(value) if isinstance(value, Mapping) else {name: value}


def _warn(warnings, message):
    if warnings is None:
        _LOG.warning("%s", message)
    else:
        warnings.append(message)
