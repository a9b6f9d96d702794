"""Helpers shared by the rostest clients: waiting for messages, the /rosout guard.

rostest runs each client as a script (its folder on ``sys.path``); importing this module also
puts ``test/`` there, for what every tier shares (``from repo import REPO``)."""
import os
import sys
import threading
import time
import unittest

import rosgraph.masterapi
import rospy
from rosgraph_msgs.msg import Log

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.realpath(__file__))))

PKG = "epuck_vrep_compat"


def call(name, **fields):
    """Call /vrep/<name> (a vrep_common service) with the request's fields."""
    import vrep_common.srv
    service = getattr(vrep_common.srv, name)
    proxy = rospy.ServiceProxy("/vrep/" + name, service)
    return proxy.call(service._request_class(**fields))


def handle(name):
    """simRosGetObjectHandle: the handle, -1 for no such object."""
    return call("simRosGetObjectHandle", objectName=name).handle


def wait_for_message(topic, msg_class, timeout_s=20.0):
    return rospy.wait_for_message(topic, msg_class, timeout=timeout_s)


class Collector:
    """Keeps every message of a topic (with the wall time it arrived)."""

    def __init__(self, topic, msg_class):
        self.messages = []
        self._lock = threading.Lock()
        self._sub = rospy.Subscriber(topic, msg_class, self._cb, queue_size=1000)

    def _cb(self, msg):
        with self._lock:
            self.messages.append(msg)

    def wait(self, count, timeout_s=20.0):
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            with self._lock:
                if len(self.messages) >= count:
                    return list(self.messages)
            time.sleep(0.02)
        raise AssertionError(f"only {len(self.messages)} of {count} messages on "
                             f"{self._sub.resolved_name} within {timeout_s} s")

    def latest(self):
        with self._lock:
            return self.messages[-1] if self.messages else None

    def wait_for(self, predicate, timeout_s=30.0, what="the expected value"):
        """The latest message once ``predicate(latest)`` holds (waiting for the first message
        too: a test must not assume that a topic arrived before another); AssertionError
        naming the last message after ``timeout_s``."""
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            last = self.latest()
            if last is not None and predicate(last):
                return last
            time.sleep(0.02)
        raise AssertionError(f"{self._sub.resolved_name} never showed {what} within "
                             f"{timeout_s} s; last: {self.latest()}")

    def clear(self):
        with self._lock:
            self.messages = []

    def get_num_connections(self):
        return self._sub.get_num_connections()

    def unregister(self):
        self._sub.unregister()


class RosoutGuard:
    """Records ERROR/FATAL lines (and warnings, for tests that expect them) on /rosout."""

    def __init__(self):
        self.errors = []
        self.warnings = []
        self._sub = rospy.Subscriber("/rosout", Log, self._cb, queue_size=1000)

    def _cb(self, msg):
        if msg.level >= Log.ERROR:
            self.errors.append(f"{msg.name}: {msg.msg}")
        elif msg.level == Log.WARN:
            self.warnings.append(f"{msg.name}: {msg.msg}")


def sim_time_now():
    return rospy.get_rostime().to_sec()


def wait_sim_time(seconds, timeout_s=60.0):
    """Sleep ``seconds`` of simulation time (fails if the clock stalls)."""
    start = sim_time_now()
    deadline = time.monotonic() + timeout_s
    while sim_time_now() - start < seconds:
        if time.monotonic() > deadline:
            raise AssertionError(f"simulation time advanced only {sim_time_now() - start:.3f} s "
                                 f"of {seconds} s in {timeout_s} s")
        time.sleep(0.01)


class SimTestCase(unittest.TestCase):
    """The rostest clients' common start, once per class: the test's node (``NODE``), a
    ``/rosout`` guard (``cls.guard``; none if ``GUARD`` is False), then the simulator waited
    for, in this order: each of ``SERVICES``, one message of ``FIRST_MESSAGE`` (topic, type),
    and ``SIM_TIME_S`` of simulation time. A class adds its own set-up after
    ``super().setUpClass()``."""

    NODE = None
    GUARD = True
    SERVICES = ()
    SERVICE_TIMEOUT_S = 60.0
    FIRST_MESSAGE = None
    MESSAGE_TIMEOUT_S = 20.0
    SIM_TIME_S = 0.0

    @classmethod
    def setUpClass(cls):
        rospy.init_node(cls.NODE)
        if cls.GUARD:
            cls.guard = RosoutGuard()
        for service in cls.SERVICES:
            rospy.wait_for_service(service, timeout=cls.SERVICE_TIMEOUT_S)
        if cls.FIRST_MESSAGE is not None:
            topic, msg_class = cls.FIRST_MESSAGE
            wait_for_message(topic, msg_class, timeout_s=cls.MESSAGE_TIMEOUT_S)
        if cls.SIM_TIME_S:
            wait_sim_time(cls.SIM_TIME_S)


def simulator_topics(node="/vrep"):
    """(published topics, subscribed topics, topic -> type) of the simulator node."""
    master = rosgraph.masterapi.Master(rospy.get_name())
    pubs, subs, _ = master.getSystemState()
    types = dict(master.getTopicTypes())
    return ({t for t, nodes in pubs if node in nodes}, {t for t, nodes in subs if node in nodes},
            types)


def master_knows(master, node="/vrep"):
    """Whether the master (a ``rosgraph.Master``) still has ``node`` as a node: any
    registration or parameter subscription of it left."""
    try:
        master.lookupNode(node)
        return True
    except rosgraph.MasterError:
        return False


def unpause_when_subscribed(subscribers, timeout_s=60.0):
    """Unpause a simulator started paused once every subscriber (or Collector) is connected,
    so they miss nothing from the first step on."""
    from std_srvs.srv import Empty
    deadline = time.monotonic() + timeout_s
    while any(s.get_num_connections() == 0 for s in subscribers):
        if time.monotonic() > deadline:
            raise AssertionError("the simulator's topics never connected")
        time.sleep(0.05)
    rospy.wait_for_service("/vrep/unpause", timeout=timeout_s)
    rospy.ServiceProxy("/vrep/unpause", Empty)()


def stepped_robot(test_class, robot="ePuck0"):
    """A paused simulator's client on ``test_class``: ``step`` (``/vrep/step``), ``truth``
    (the robot's ground truth, collected), ``cmd`` (its cmd_vel, connected when it returns)."""
    from geometry_msgs.msg import Twist
    from nav_msgs.msg import Odometry

    from epuck_vrep_compat.srv import StepSimulation
    rospy.wait_for_service("/vrep/step", timeout=30)
    test_class.step = rospy.ServiceProxy("/vrep/step", StepSimulation, persistent=True)
    test_class.truth = Collector(f"/{robot}/ground_truth", Odometry)
    test_class.cmd = rospy.Publisher(f"/{robot}/cmd_vel", Twist, queue_size=1)
    deadline = time.monotonic() + 20
    while test_class.cmd.get_num_connections() == 0 and time.monotonic() < deadline:
        time.sleep(0.05)


def pose_of(odometry):
    """(x, y, yaw) of a nav_msgs/Odometry (ground truth)."""
    from epuck_vrep_compat.geometry.transforms import yaw_of
    p, q = odometry.pose.pose.position, odometry.pose.pose.orientation
    return p.x, p.y, float(yaw_of((q.x, q.y, q.z, q.w)))


def learn_test_setup(node_name):
    """The learning rostests' start: the node, a /rosout guard, the profile's names
    (``~profile``) and the scene (``~world``)."""
    from epuck_vrep_compat.compat.epuck_names import PROFILE_NAMES
    from epuck_vrep_compat.scene.scene_file import load_scene
    rospy.init_node(node_name)
    return (RosoutGuard(), PROFILE_NAMES[rospy.get_param("~profile")],
            load_scene(rospy.get_param("~world")))
