"""The robots' names from a names list (launch argument ``names``, parameter ``~robot_names``).

A name is a ROS namespace: ``epuck_7``, ``team_a/epuck_1``, or ``/`` for one robot whose topics
sit at the root (``/proximity0``, ``/mobile_base/cmd_vel``), as the drivers' single-robot
launches give them. Frames follow the name (``epuck_7/base_link``; the root robot's frames carry
the profile's ``root_frame_prefix``). V-REP's object names (``ePuck#0``) do not depend on it.

:func:`parse_robot_names` refuses a list the simulator cannot run with (``ValueError`` naming
the entry); :func:`unconventional_names` lists names the original would not give, which work
but are worth a warning (a client written for the original may not find them).
"""
import re
from typing import List, Sequence

from epuck_vrep_compat.compat.epuck_names import ROOT_NAMESPACE, ProfileNames

_SEGMENT = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")


def _normalise(entry) -> str:
    if not isinstance(entry, str):
        raise ValueError(f"entry {entry!r} is not a string")
    if entry.strip() == ROOT_NAMESPACE:
        return ROOT_NAMESPACE
    name = entry.strip().strip("/")
    segments = name.split("/")
    if not name or not all(_SEGMENT.match(s) for s in segments):
        raise ValueError(f"entry {entry!r} is not a ROS namespace (segments of letters, digits "
                         "and '_', each starting with a letter), nor '/' for the root")
    return name


def parse_robot_names(value, profile: ProfileNames) -> List[str]:
    """The names of a names list: a list of strings, or one string of names separated by
    commas or spaces. ValueError, naming the entry, for an unusable list."""
    if isinstance(value, str):
        value = [v for v in re.split(r"[,\s]+", value) if v]
    if not isinstance(value, (list, tuple)) or not value:
        raise ValueError(f"must be a non-empty list of robot names, got {value!r}")
    names = [_normalise(v) for v in value]
    prefixes = {}
    for name in names:
        prefix = profile.frame_prefix(name)
        if prefix in prefixes:
            raise ValueError(f"entry {name!r} repeats {prefixes[prefix]!r} (names and their "
                             f"frame prefixes must be unique; the root robot's is {prefix!r})"
                             if name != prefixes[prefix] else f"entry {name!r} appears twice")
        prefixes[prefix] = name
    if ROOT_NAMESPACE in names and len(names) > 1:
        raise ValueError("'/' (the root namespace, the single-robot layout) must be the only "
                         f"name, got {names}")
    return names


def unconventional_names(names: Sequence[str], profile: ProfileNames) -> List[str]:
    """The names the original's launch files would not give (they work all the same): not of
    the profile's form (``ePuck3``, ``epuck_robot_3``)."""
    before, _, after = profile.robot_name_format.partition("{index}")
    pattern = re.compile(rf"^{re.escape(before)}\d+{re.escape(after)}$")
    return [n for n in names if n != ROOT_NAMESPACE and not pattern.match(n)]
