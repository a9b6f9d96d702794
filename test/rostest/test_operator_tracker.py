#!/usr/bin/python3
"""operator_tracker against the operator's ground truth (his TF frame at each estimate's stamp)
over full walks of worlds/merlin_safety.yaml: position error mean and 95th percentile bounded;
with camera 1 removed through /vrep the track goes on, with a larger covariance."""
import threading
import time

import numpy as np
import rospy
import rostest
import tf2_ros
from geometry_msgs.msg import PoseWithCovarianceStamped

from sim_test_helpers import SimTestCase, call, handle, wait_sim_time

WALK_CYCLE_S = 2 * 3.2 / 1.6      # out and back along the 3.2 m path at 1.6 m/s


class Track:
    """Every estimate with the operator's true position at its stamp."""

    def __init__(self):
        self.tf = tf2_ros.Buffer(cache_time=rospy.Duration(60))
        self._listener = tf2_ros.TransformListener(self.tf)
        self._lock = threading.Lock()
        self.pending = []
        self._sub = rospy.Subscriber("/operator_tracker/pose", PoseWithCovarianceStamped,
                                     self._on_pose, queue_size=100)

    def _on_pose(self, msg):
        with self._lock:
            self.pending.append(msg)

    def collect(self, seconds):
        """(errors m, position variances m^2: P_xx + P_yy) over seconds of simulated time."""
        with self._lock:
            self.pending = []
        wait_sim_time(seconds)
        time.sleep(0.5)
        with self._lock:
            msgs = list(self.pending)
        errors, variances = [], []
        for msg in msgs:
            t = self.tf.lookup_transform("world", "Bill", msg.header.stamp,
                                         rospy.Duration(2.0)).transform.translation
            p = msg.pose.pose.position
            errors.append(float(np.hypot(p.x - t.x, p.y - t.y)))
            variances.append(msg.pose.covariance[0] + msg.pose.covariance[7])
        return np.array(errors), np.array(variances)


class OperatorTracking(SimTestCase):
    NODE = "test_operator_tracker"
    FIRST_MESSAGE = ("/operator_tracker/pose", PoseWithCovarianceStamped)
    MESSAGE_TIMEOUT_S = 60.0

    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        cls.track = Track()
        wait_sim_time(1.0)

    def report(self, what, errors, variances):
        rospy.loginfo("%s: %d estimates, error mean %.3f m, 95th pct %.3f m, max %.3f m; "
                      "mean position variance %.4f m^2", what, len(errors), errors.mean(),
                      np.percentile(errors, 95), errors.max(), variances.mean())

    def test_1_error_bounded_then_one_camera_removed(self):
        errors, variances = self.track.collect(2 * WALK_CYCLE_S)
        self.report("both cameras, the laser and the Kinect", errors, variances)
        self.assertGreater(len(errors), 0.8 * 20 * 2 * WALK_CYCLE_S)   # 20 Hz held
        self.assertLess(errors.mean(), 0.12)
        self.assertLess(np.percentile(errors, 95), 0.3)
        self.assertEqual(call("simRosRemoveObject", handle=handle("camera")).result, 1)
        wait_sim_time(0.5)
        errors1, variances1 = self.track.collect(2 * WALK_CYCLE_S)
        self.report("camera 1 removed", errors1, variances1)
        self.assertGreater(len(errors1), 0.8 * 20 * 2 * WALK_CYCLE_S)  # the track goes on
        self.assertLess(errors1.mean(), 0.25)
        self.assertLess(np.percentile(errors1, 95), 0.6)
        self.assertGreater(variances1.mean(), variances.mean())

    def test_9_no_errors_logged(self):
        self.assertEqual(self.guard.errors, [])


if __name__ == "__main__":
    rostest.rosrun("epuck_vrep_compat", "test_operator_tracker", OperatorTracking)
