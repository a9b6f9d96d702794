"""The simulator node publishes the same whatever the order of its faces list (no master).

Each run builds the whole node (every face, ``/clock``, the step batch) in a process of its own
(rospy's topics are per process), with a fake subscriber on every topic the moment it is
advertised, drives it with one fixed command log (through its subscribers, and a ``/vrep``
get_transform stream enabled as the service does), and reports every topic's bytes. The faces
list as the node builds it, reversed and shuffled must give the same bytes on every topic, in
the e-pucks' arena and in the MERLIN cell. Before, they did not: the blob streams (``/vrep``
publishes what the cell's scripts declare) needed the cell's face first, and ``/tf``, which the
e-pucks', the cell's and ``/vrep``'s faces share, got their messages in the list's order.

The e-pucks' ``ground_truth`` is not published here: its forward speed differs by one ulp now
and then between two runs of one order (before this test's change too; its inputs, the swarm's
poses and velocities, do not), which is no question of the faces' order.
"""
import hashlib
import json
import os
import random
import socket
import subprocess
import sys

import pytest

from repo import REPO

STEPS = 40
SCENES = {"epucks": (os.path.join(REPO, "worlds", "arena.yaml"), 3),
          "cell": (os.path.join(REPO, "worlds", "merlin_cell.yaml"), 2)}
ORDERS = ("built", "reversed", "shuffled")
TRANSFORM_STREAM = "simRosEnablePublisher get_transform"     # of an object, to the world


def commands():
    """step -> [(topic, message)]: the same command log for every run."""
    from geometry_msgs.msg import Twist, Vector3
    from sensor_msgs.msg import JointState
    from std_msgs.msg import Float64, UInt8MultiArray

    def twist(x, y, w):
        return Twist(linear=Vector3(x, y, 0.0), angular=Vector3(0.0, 0.0, w))
    return {
        1: [(TRANSFORM_STREAM, "ePuck")],
        2: [("/ePuck0/cmd_vel", twist(0.05, 0.0, 0.5)), ("/ePuck1/cmd_vel", twist(0.1, 0, -1.0)),
            ("/ePuck0/cmd_led", UInt8MultiArray(data=bytes([1, 0, 1, 0, 1, 0, 1, 0, 1])))],
        5: [("/ePuck1/cmd_vel", twist(float("nan"), 0.0, 0.0)),
            ("/IRB140/joint_command", JointState(name=["IRB140_joint1", "nope"],
                                                 position=[0.5, 0.1])),
            ("/youBot/cmd_vel", twist(0.3, 0.1, 0.2)),
            ("/SIX/speed_scale", Float64(0.5))],
        9: [("/SIX/joint_command", JointState(velocity=[0.2] * 6 + [50.0])),
            ("/ePuck0/cmd_led", UInt8MultiArray(data=bytes([0] * 9))),
            ("/youBot/cmd_vel", twist(5.0, 0.0, 0.0))],
    }


class Connection:
    """A subscriber's connection as rospy's publisher and the step batch see one; keeps what
    rospy writes and reads what the batch's writer sends on its socket."""

    def __init__(self, topic):
        self.endpoint_id = topic
        self.done = False
        self.stat_bytes = 0
        self.written = bytearray()
        self.received = bytearray()
        self.socket, self._peer = socket.socketpair()
        self._peer.setblocking(False)
        self.cleanup_cb = None

    def set_cleanup_callback(self, callback):
        self.cleanup_cb = callback

    def write_data(self, data):
        self.written += data

    def fileno(self):
        return self.socket.fileno()

    def close(self):
        self.done = True

    def drain(self):
        while True:
            try:
                chunk = self._peer.recv(1 << 20)
            except BlockingIOError:
                return
            if not chunk:
                return
            self.received += chunk


def frames(data: bytes):
    out, i = [], 0
    while i < len(data):
        size = int.from_bytes(data[i:i + 4], "little")
        out.append(bytes(data[i:i + 4 + size]))
        i += 4 + size
    return out


def enable_transform_stream(node, object_name):
    """What ``/vrep/simRosEnablePublisher`` does for a client's get_transform stream."""
    from vrep_common.srv import simRosEnablePublisherRequest

    from epuck_vrep_compat.compat import vrep_codes as vc
    with node._lock:                          # as the service handler
        handle = node.vrep.backend.object_handle(object_name)
        name = node.vrep.streams.enable_publisher(simRosEnablePublisherRequest(
            "tf_" + object_name, 1, vc.STRMCMD_GET_TRANSFORM, handle, -1, "")).effectiveTopicName
    assert name, f"no get_transform stream of {object_name}"


def record(scene: str, order: str) -> dict:
    """Run the node on ``scene`` with its faces in ``order``: topic -> digest of its bytes."""
    import rospy
    import rospy.core
    import rospy.topics
    from rospy.impl.registration import get_topic_manager

    rospy.core._client_ready = True          # no master: the topics work locally
    rospy.set_param = lambda name, value: None
    rospy.delete_param = lambda name: None
    rospy.Service = lambda *args, **kwargs: None
    connections = {}
    advertise = rospy.topics.Publisher.__init__

    def advertise_and_subscribe(self, *args, **kwargs):
        advertise(self, *args, **kwargs)
        impl = self.impl
        if impl.resolved_name not in connections:
            impl.queue_size = None           # rospy's own writes at once, none dropped
            connections[impl.resolved_name] = connection = Connection(impl.resolved_name)
            impl.add_connection(connection)
    rospy.topics.Publisher.__init__ = advertise_and_subscribe

    from epuck_vrep_compat.ros.epuck.profiles import PROFILES
    from epuck_vrep_compat.ros.node.params import SimParams
    from epuck_vrep_compat.ros.node.simulator_node import SimulatorNode
    world, n = SCENES[scene]
    params = SimParams(world=world, n=n, robot_names=[PROFILES["vrep"].robot_name(i)
                                                      for i in range(n)], seed=7, rtf=0.0,
                       publish_ground_truth=False)
    node = SimulatorNode(params, os.path.join(REPO, "models"))
    if order == "reversed":
        node.faces.reverse()
    elif order == "shuffled":
        random.Random(23).shuffle(node.faces)
    log = commands()
    for k in range(STEPS):
        for topic, msg in log.get(k, ()):
            if topic == TRANSFORM_STREAM:
                enable_transform_stream(node, msg)
                continue
            impl = get_topic_manager().get_subscriber_impl(topic)
            if impl is not None:
                impl.receive_callback([msg], None)
        assert node._step_and_publish()      # the loop's step, without its clock
        node._batch.flush()
        node._batch.settle()
        for connection in connections.values():
            connection.drain()
    out = {}
    for topic, connection in connections.items():
        for path, data in (("batch", connection.received), ("rospy", connection.written)):
            if data:
                out[f"{topic} ({path})"] = [len(frames(bytes(data))),
                                            hashlib.sha256(bytes(data)).hexdigest()]
    return out


def run(scene: str, order: str) -> dict:
    tests = os.path.join(REPO, "test")          # for the child's own `from repo import REPO`
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(
        p for p in (tests, os.environ.get("PYTHONPATH")) if p))
    done = subprocess.run([sys.executable, __file__, scene, order], capture_output=True,
                          text=True, timeout=300, env=env)
    assert done.returncode == 0, done.stderr[-3000:]
    return json.loads(done.stdout.splitlines()[-1])


@pytest.mark.parametrize("scene", sorted(SCENES))
def test_the_faces_order_does_not_change_what_any_topic_gets(scene):
    runs = {order: run(scene, order) for order in ORDERS}
    built = runs["built"]
    assert len(built) > 10
    if scene == "cell":                       # the case the order used to decide
        assert built["/vrep/Blob_Camera_0_X (batch)"][0] > 0
    for order in ORDERS[1:]:
        differ = sorted(t for t in set(built) | set(runs[order])
                        if built.get(t) != runs[order].get(t))
        assert differ == [], f"{order}: " + "; ".join(
            f"{t}: {built.get(t)} != {runs[order].get(t)}" for t in differ)


if __name__ == "__main__":
    print(json.dumps(record(sys.argv[1], sys.argv[2])))
    sys.stdout.flush()
    os._exit(0)                               # the batch's writer thread need not be joined
