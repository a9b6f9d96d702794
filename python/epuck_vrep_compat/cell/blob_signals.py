"""The ceiling cameras' blobs as V-REP signals, as the thesis's child script made them: each
step a blob camera's first blob x and y become the float signals its ``blob_topics`` name, and
are cleared while it sees no blob; those signals are published from every start on (the cell
declares them, ``Cell.published_signals``; the ``/vrep`` face enables ``/vrep/Blob_Camera_0_X``
...).
"""


def blob_signal_names(camera_specs):
    """The float signals of every blob camera, x then y, in the cameras' order."""
    return [name for c in camera_specs for name in c.blob_topics]


def write_blob_signals(floats, camera_specs, blobs):
    """``floats``: the simulation's float signals; ``blobs``: camera name -> V-REP's blob
    packet of this step."""
    for c in camera_specs:
        if not c.blob_topics:
            continue
        packet = blobs.get(c.name)
        x_topic, y_topic = c.blob_topics
        if packet is not None and len(packet) > 6 and packet[0] >= 1:
            floats[x_topic] = float(packet[4])
            floats[y_topic] = float(packet[5])
        else:
            floats.pop(x_topic, None)
            floats.pop(y_topic, None)
