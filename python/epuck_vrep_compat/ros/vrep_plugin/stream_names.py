"""Names of the legacy plugin's streams: topic names, stream identity and frame ids (pure logic).

V-REP 3.3.0's ``ROS_server`` (``addPublisher``, ``getPublisherIndexFromCmd``,
``objNameToFrameId``) is the reference:

* a requested topic name is sanitised (``#``, ``-``, ``(``, ``)`` spelled out) and is relative
  to ``/vrep/`` unless it starts with ``/``; a taken name (or ``info``) gets ``_2`` appended,
  again and again until it is free (``a``, ``a_2``, ``a_2_2``: V-REP's scheme, not ``a_3``);
* two requests are the same stream when the command and the aux arguments of the command's
  group are equal (``_IDENTITY_BY_GROUP``);
* a frame id is ``"/" + objectName`` sanitised, unless a get_transform stream's
  ``"child%parent"`` auxString renamed that object's frame (then for every stream).
"""
from dataclasses import dataclass

from epuck_vrep_compat.compat.topics import INFO_TOPIC, NODE_NAMESPACE

COLLISION_SUFFIX = "_2"
_MARKS = (("#", "_HASHMARK_"), ("-", "_MINUSMARK_"), ("(", "_OPARENTHESISMARK_"),
          (")", "_CPARENTHESISMARK_"))


def sanitize(name: str) -> str:
    """V-REP 3.3.0's replacement of the characters ROS names cannot hold."""
    for mark, word in _MARKS:
        name = name.replace(mark, word)
    return name


def resolve_topic(name: str) -> str:
    """The full ROS name of a stream topic: absolute as given, else under ``/vrep/``."""
    return name if name.startswith("/") else NODE_NAMESPACE + name


def unique_topic_name(requested: str, taken) -> str:
    """The sanitised name, with ``_2`` appended while ``taken(resolved name)`` is true or the
    name is the always-on ``info`` stream."""
    name = sanitize(requested)
    while resolve_topic(name) == INFO_TOPIC or taken(resolve_topic(name)):
        name += COLLISION_SUFFIX
    return name


@dataclass(frozen=True)
class Aux:
    """The aux arguments of an enable request."""

    int1: int = 0
    int2: int = 0
    string: str = ""


# Which aux arguments identify a stream, by the command's 0x1000 group (none for the others)
_IDENTITY_BY_GROUP = {0x1000: lambda aux: (aux.int1,),
                      0x2000: lambda aux: (aux.int1, aux.int2),
                      0x3000: lambda aux: (aux.string,),
                      0x4000: lambda aux: (aux.int1, aux.string)}


def stream_identity(stream_cmd: int, aux: Aux):
    """What makes two enable requests the same publisher: the command and its group's aux."""
    key = _IDENTITY_BY_GROUP.get(stream_cmd & ~0x0FFF)
    return (stream_cmd,) + (key(aux) if key else ())


class FrameNames:
    """Object name -> frame id, with the renames get_transform streams made (cleared when the
    simulation ends, as the plugin's ``renamedFrames``)."""

    def __init__(self):
        self._renamed = {}

    def frame_id(self, object_name: str) -> str:
        renamed = self._renamed.get(object_name)
        if renamed is not None:
            return renamed
        return sanitize(object_name if object_name.startswith("/") else "/" + object_name)

    def transform_frames(self, child_name: str, parent_name: str, override: str):
        """(child frame, parent frame) of a get_transform stream; ``override`` is its auxString
        ``"child%parent"`` (either side may be empty), which also renames both objects'
        frames for every stream."""
        child, parent = child_name, parent_name
        if override:
            pos = override.find("%")
            if pos != 0:
                child = override if pos < 0 else override[:pos]
            if 0 <= pos < len(override) - 1:
                parent = override[pos + 1:]
        child_frame, parent_frame = self.frame_id(child), self.frame_id(parent)
        if override:
            self._renamed[child_name] = child_frame
            self._renamed[parent_name] = parent_frame
        return child_frame, parent_frame

    def clear(self):
        self._renamed.clear()


__all__ = ["Aux", "FrameNames", "resolve_topic", "sanitize", "stream_identity",
           "unique_topic_name"]
