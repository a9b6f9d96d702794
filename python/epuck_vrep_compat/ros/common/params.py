"""Private parameters of every node of this package, read and validated in one place.

An unusable value raises :class:`ParamError` naming the parameter; the simulator node and the
client nodes then exit non-zero. Used by the simulator node (``ros/node/params.py``) and by the
thesis's client nodes (``thesis/params.py``).
"""
import math
from typing import Sequence, Tuple

import rospy


class ParamError(ValueError):
    """A parameter value the node cannot run with."""


def read_typed(name, default, kind, check=None, what=""):
    """``~name`` as ``kind`` (int, float, bool or str; an integral float is an int, an int a
    float), finite if a float, and passing ``check`` (else ``what`` says what it must be)."""
    value = rospy.get_param("~" + name, default)
    if kind is float and isinstance(value, int) and not isinstance(value, bool):
        value = float(value)
    if kind is int and isinstance(value, float) and value.is_integer():
        value = int(value)
    if not isinstance(value, kind) or isinstance(value, bool) != (kind is bool):
        raise ParamError(f"parameter '~{name}' must be {kind.__name__}, got {value!r}")
    if kind is float and not math.isfinite(value):
        raise ParamError(f"parameter '~{name}' must be finite, got {value!r}")
    if check is not None and not check(value):
        raise ParamError(f"parameter '~{name}' {what}, got {value!r}")
    return value


def _is_number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def read_float(key: str, default: float, minimum: float = 0.0) -> float:
    """A finite number above ``minimum``."""
    value = rospy.get_param("~" + key, default)
    if not _is_number(value) or not math.isfinite(value) or value <= minimum:
        raise ParamError(f"parameter '~{key}' must be a finite number > {minimum}, got {value!r}")
    return float(value)


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
