"""Private parameters of the thesis's nodes: read once at start-up, validated.

An unusable value raises :class:`ParamError` naming the parameter; the node then exits with
code 2 (see :func:`epuck_vrep_compat.thesis.vrep_client.run_node`).
"""
import math
from typing import Sequence, Tuple

import rospy

DEFAULT_RATE_HZ = 20.0


class ParamError(ValueError):
    """A parameter value the node cannot run with."""


def _is_number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def read_float(key: str, default: float, minimum: float = 0.0) -> float:
    """A finite number above ``minimum``."""
    value = rospy.get_param("~" + key, default)
    if not _is_number(value) or not math.isfinite(value) or value <= minimum:
        raise ParamError(f"parameter '~{key}' must be a finite number > {minimum}, got {value!r}")
    return float(value)


def read_rate_hz() -> float:
    return read_float("rate", DEFAULT_RATE_HZ)


def read_name(key: str, default: str) -> str:
    """A V-REP object name: a non-empty string."""
    value = rospy.get_param("~" + key, default)
    if not isinstance(value, str) or not value:
        raise ParamError(f"parameter '~{key}' must be a non-empty object name, got {value!r}")
    return value


def read_names(key: str, defaults: Sequence[str], exact_count: bool = True) -> Tuple[str, ...]:
    """A list of V-REP object names; with ``exact_count`` as many as ``defaults`` (the thesis's
    messages have fixed-size arrays)."""
    value = rospy.get_param("~" + key, list(defaults))
    if (not isinstance(value, (list, tuple)) or not value
            or not all(isinstance(v, str) and v for v in value)):
        raise ParamError(f"parameter '~{key}' must be a list of object names, got {value!r}")
    if exact_count and len(value) != len(defaults):
        raise ParamError(f"parameter '~{key}' must list exactly {len(defaults)} names, got "
                         f"{len(value)}")
    return tuple(value)
