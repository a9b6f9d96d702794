"""The cell's laser scanner on ``/vrep/<laser topic>`` (``sensor_msgs/LaserScan``, default
``/vrep/front_scan``) at the scanner's rate, as V-REP's ROS-enabled Hokuyo model did, with the
real URG-04LX-UG01's angles, step count and range limits; its frame is the scanner's object
name."""
import math

from sensor_msgs.msg import LaserScan

from epuck_vrep_compat.ros.transport.step_batch import synchronous_publisher


class LaserTopic:
    """The laser's topic: one message per scan the cell took (``Cell.scan_count``)."""

    def __init__(self, cell):
        self._cell = cell
        self._publisher = synchronous_publisher("~" + cell.laser.topic, LaserScan)
        self._msg = laser_message(cell.laser)
        self._scans_seen = 0

    def close(self):
        self._publisher.unregister()

    def publish(self, batch, stamp):
        """After a step: the scan, if the cell took one since the last step."""
        cell = self._cell
        if cell.scan_count == self._scans_seen:
            return
        self._scans_seen = cell.scan_count
        if batch.wanted(self._publisher):
            msg = self._msg
            msg.header.stamp = stamp
            msg.ranges = cell.laser_ranges.tolist()
            batch.add(self._publisher, msg)


def laser_message(s) -> LaserScan:
    """The scan's fixed fields, from the scanner's spec ``s``."""
    msg = LaserScan()
    msg.header.frame_id = s.name
    msg.angle_min = s.angle_min_rad
    msg.angle_increment = s.angle_increment_rad
    msg.angle_max = s.angle_min_rad + (s.count - 1) * s.angle_increment_rad
    msg.scan_time = 1.0 / s.rate_hz
    # a 600 rpm mirror sweeps one step of 2*pi/1024 in scan_time/1024... of a full turn
    msg.time_increment = msg.scan_time * s.angle_increment_rad / (2.0 * math.pi)
    msg.range_min = s.range_min_m
    msg.range_max = s.range_max_m
    return msg
