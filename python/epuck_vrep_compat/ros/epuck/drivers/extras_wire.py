"""Pre-laid-out wire formats of the drivers' extra topics, so a step writes only numbers.

:func:`sentinel_batch` turns one genpy message per robot (built by ``extras_messages``, so the
fixed fields are the driver's) into a :class:`~epuck_vrep_compat.ros.transport.wire.
MessageBatch`: each per-step field is found in the serialised body by writing sentinel values
into it, so no offset is computed by hand. Text markers (their length changes with the text)
are kept serialised per robot and text, and only their stamp is rewritten each step.
"""
import struct

import numpy as np

from epuck_vrep_compat.ros.transport.step_batch import wire_bytes
from epuck_vrep_compat.ros.transport.wire import MessageBatch

_STAMP = struct.Struct("<2I")
_LENGTH = struct.Struct("<I")


def _sentinels(dtype, field_index, count):
    base = {"<f8": -7.0e-290, "<f4": -3.0e-30}[dtype]
    return [base * (1.0 + 0.125 * (16 * field_index + j)) for j in range(count)]


def sentinel_batch(msgs, fields) -> MessageBatch:
    """``msgs``: one genpy message per row (with a header); ``fields``: name -> (setter(msg,
    values), dtype "<f8" or "<f4", count). ValueError when a sentinel is not found once."""
    bodies, offsets = [], {name: [] for name in fields}
    for msg in msgs:
        for k, (setter, dtype, count) in enumerate(fields.values()):
            setter(msg, _sentinels(dtype, k, count))
        body = wire_bytes(msg)
        for k, (name, (_setter, dtype, count)) in enumerate(fields.items()):
            pattern = np.array(_sentinels(dtype, k, count), dtype=dtype).tobytes()
            at = body.find(pattern)
            if at < 0 or body.find(pattern, at + 1) >= 0:
                raise ValueError(f"field '{name}' not found once in {type(msg).__name__}")
            offsets[name].append(at)
        bodies.append(body)
    return MessageBatch(type(msgs[0]), bodies,
                        {name: (offsets[name], dtype, count)
                         for name, (_s, dtype, count) in fields.items()})


class TextMarkerCache:
    """Framed text markers by (robot, topic), re-serialised only when their text changes."""

    def __init__(self):
        self._frames = {}        # (robot, topic) -> (text, bytearray frame)

    def frame(self, key, text, build, secs, nsecs) -> bytes:
        """The framed marker of ``text`` stamped (secs, nsecs); ``build()`` makes the message
        when the text is new."""
        entry = self._frames.get(key)
        if entry is None or entry[0] != text:
            body = wire_bytes(build())
            entry = self._frames[key] = (text, bytearray(_LENGTH.pack(len(body)) + body))
        frame = entry[1]
        _STAMP.pack_into(frame, 8, secs, nsecs)     # length (4), seq (4), then the stamp
        return bytes(frame)

    def forget(self, robot):
        for key in [k for k in self._frames if k[0] == robot]:
            del self._frames[key]
