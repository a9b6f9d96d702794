"""Checks shared by the file parsers (scene files, their ``cell:`` section, model files).

Every check takes the value and ``where`` (the key's path in the file) and raises
:class:`SceneError` naming that key, so a malformed file gets a message that says what to fix.
"""
import math

import yaml


class SceneError(ValueError):
    """A scene file that cannot be used; the message names the key."""


def read_yaml(path: str, what: str, quote: bool = True):
    """The content of a YAML file; SceneError saying which ``what`` could not be read.
    ``quote=False``: a syntax error names its line and column, never the file's text (for
    files a remote caller names)."""
    try:
        with open(path, "r", encoding="utf-8") as f:
            return yaml.safe_load(f)
    except OSError as e:
        raise SceneError(f"cannot read {what} '{path}': {e.strerror}") from e
    except UnicodeDecodeError as e:
        raise SceneError(f"{what} '{path}' is not UTF-8 text") from e
    except yaml.YAMLError as e:
        if quote:
            raise SceneError(f"{what} '{path}' is not valid YAML: {e}") from e
        mark = getattr(e, "problem_mark", None)
        where = f" at line {mark.line + 1}, column {mark.column + 1}" if mark else ""
        raise SceneError(f"{what} '{path}' is not valid YAML{where}") from e


def only(d, allowed, where):
    """No key of mapping ``d`` outside ``allowed``."""
    unknown = sorted(set(d) - allowed)
    if unknown:
        raise SceneError(f"{where}: unknown key(s) {unknown}; allowed: {sorted(allowed)}")


def as_list(v, where):
    """``v`` itself, which must be a list."""
    if not isinstance(v, list):
        raise SceneError(f"{where} must be a list")
    return v


def number(v, where) -> float:
    """A finite number (not a bool), as a float."""
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise SceneError(f"{where} must be a finite number, got {v!r}")
    return float(v)


def positive(v, where) -> float:
    """A finite number above zero, as a float."""
    x = number(v, where)
    if x <= 0.0:
        raise SceneError(f"{where} must be positive, got {v!r}")
    return x


def numbers(v, n, where, positive=False):
    """A list of exactly ``n`` finite numbers (each above zero when ``positive``)."""
    if not isinstance(v, (list, tuple)) or len(v) != n:
        raise SceneError(f"{where} must be a list of {n} numbers, got {v!r}")
    check = _positive if positive else number
    return [check(x, where) for x in v]


_positive = positive     # the function, where the parameter ``positive`` shadows it


def color(v, where):
    """An RGB triple with components in 0..1, as a tuple."""
    c = numbers(v, 3, where)
    if any(x < 0.0 or x > 1.0 for x in c):
        raise SceneError(f"{where} components must be in 0..1, got {v!r}")
    return tuple(c)
