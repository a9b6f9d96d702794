"""The sensor subset's logic (no master): the IRB's proximity sensors picked by name out of
every sensor of the scene, the Kinect's depth buffer in V-REP's units and in metres."""
import math

import numpy as np
import rospy
from std_msgs.msg import Header

from epuck_vrep_compat.thesis.cameras import stamp_header
from epuck_vrep_compat.thesis.kinect import depth_buffer_message, depth_image
from epuck_vrep_compat.thesis.prox_sensors import (
    prox_message, readings_by_handle, sensor_handles)


def test_sensors_are_picked_by_name_in_parameter_order():
    names = {30: "Proximity_sensor11", 20: "ePuck_proxSensor0", 31: "Proximity_sensor10"}
    sensors = sensor_handles(["Proximity_sensor10", "Proximity_sensor11", "Proximity_sensor12"],
                             names)
    assert sensors == [("Proximity_sensor10", 31), ("Proximity_sensor11", 30),
                       ("Proximity_sensor12", -1)]


def test_prox_message_from_data_type_13():
    # the scene's sensors in handle order: an e-puck's, then two of the IRB's
    readings = readings_by_handle([20, 30, 31], [0, -1, 1, 77, 0, -1],
                                  [0.0] * 6 + [0.01, 0.02, 0.05, 0.0, 0.0, -1.0] + [0.0] * 6)
    msg = prox_message([("Proximity_sensor10", 31), ("Proximity_sensor11", 30),
                        ("Proximity_sensor12", -1)], readings)
    got = [(p.nomeProx, p.state, p.objectHandle) for p in msg.proxData]
    assert got == [("Proximity_sensor10", 0, -1), ("Proximity_sensor11", 1, 77),
                   ("Proximity_sensor12", -1, -1)]
    assert list(msg.proxData[1].point) == [0.01, 0.02, 0.05]
    assert list(msg.proxData[1].normal) == [0.0, 0.0, -1.0]
    assert readings_by_handle([20, 30], [0, -1], [0.0] * 12) == {}      # arrays that do not fit


def test_depth_buffer_keeps_vreps_values_and_says_its_shape():
    msg = depth_buffer_message([3, 2], [0.0, 0.1, 0.2, 0.3, 0.4, 1.0])
    assert [(d.label, d.size, d.stride) for d in msg.layout.dim] == [("height", 2, 6),
                                                                     ("width", 3, 3)]
    # float32[] on the wire: the values as V-REP's float buffer holds them
    np.testing.assert_array_equal(msg.data, np.float32([0.0, 0.1, 0.2, 0.3, 0.4, 1.0]))


def test_depth_image_in_metres_top_row_first():
    # V-REP's buffer: first row = bottom of the image
    image = depth_image([3, 2], [0.0, 0.5, 1.0, 0.25, 0.75, 0.1], near_m=0.5, far_m=4.5)
    assert (image.encoding, image.width, image.height, image.step, image.is_bigendian) == (
        "32FC1", 3, 2, 12, 0)
    depth = np.frombuffer(image.data, dtype="<f4").reshape(2, 3)
    np.testing.assert_allclose(depth[0], [1.5, 3.5, 0.9], rtol=1e-6)        # V-REP's top row
    assert depth[1, 0] == 0.5 and depth[1, 1] == 2.5 and math.isinf(depth[1, 2])
    assert depth_image([3, 2], [0.0] * 5, 0.5, 4.5) is None
    assert depth_image([], [], 0.5, 4.5) is None


def test_images_get_a_stamp_and_the_sensors_name_when_the_plugin_leaves_them_empty(
        monkeypatch):
    monkeypatch.setattr(rospy, "get_rostime", lambda: rospy.Time(3, 0))
    header = Header()
    stamp_header(header, "camera0")
    assert header.stamp == rospy.Time(3, 0) and header.frame_id == "camera0"
    kept = Header(stamp=rospy.Time(1, 0), frame_id="/camera0")
    stamp_header(kept, "camera0")
    assert kept.stamp == rospy.Time(1, 0) and kept.frame_id == "/camera0"
