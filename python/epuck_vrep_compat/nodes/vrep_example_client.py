"""V-REP's rosBubbleRob example, in Python, driving an e-puck through the legacy plugin's API.

In the order of the original (``ros_bubble_rob/src/rosBubbleRob.cpp``): subscribe
``/vrep/info``; enable a read_proximity_sensor publisher with ``/vrep/simRosEnablePublisher``
and subscribe to it (any message means "something ahead"); enable a set_joint_state subscriber
on ``/<node>/wheels`` with ``/vrep/simRosEnableSubscriber``; then publish the wheel speeds
(velocity mode) every 5 ms: forward at pi rad/s, and for 3 s of simulated time backwards while
turning after a detection; exit 0 when /vrep/info says the simulation stopped.

Parameters (object names, resolved with ``/vrep/simRosGetObjectHandle``): ``~left_joint``
(ePuck_leftJoint), ``~right_joint`` (ePuck_rightJoint), ``~sensor`` (ePuck_proxSensor0).
The node name carries a suffix made from the time and process id, as the original's randId.
"""
import os
import threading
import time

import rospy
from vrep_common.msg import JointSetStateData, ProximitySensorData, VrepInfo
from vrep_common.srv import simRosEnablePublisher, simRosEnableSubscriber, simRosGetObjectHandle

from epuck_vrep_compat.compat import vrep_codes as vc
from epuck_vrep_compat.compat.epuck_names import model_object_name
from epuck_vrep_compat.compat.topics import INFO_TOPIC, NODE_NAMESPACE

FORWARD_RAD_S = (3.1415, 3.1415)
BACKWARD_RAD_S = (-3.1415 * 0.5, -3.1415 * 0.25)
BACKWARD_DURATION_S = 3.0
LOOP_PERIOD_S = 0.005          # the original's usleep(5000), wall time
SERVICE_TIMEOUT_S = 30.0


class BubbleRob:
    """The client's state, written by the /vrep/info and sensor callbacks."""

    def __init__(self):
        self._lock = threading.Lock()
        self.simulation_time = 0.0
        self.simulation_running = None      # unknown until the first /vrep/info
        self.sensor_trigger = False
        self.subscribers = []

    def on_info(self, info: VrepInfo):
        with self._lock:
            self.simulation_time = info.simulationTime.data
            self.simulation_running = (info.simulatorState.data & vc.STATE_NOT_STOPPED) != 0

    def on_sensor(self, _data: ProximitySensorData):
        with self._lock:
            self.sensor_trigger = True          # any message: something was detected

    def take_trigger(self):
        with self._lock:
            trigger, self.sensor_trigger = self.sensor_trigger, False
            return trigger


def _service(name, srv_class):
    rospy.wait_for_service(name, timeout=SERVICE_TIMEOUT_S)
    return rospy.ServiceProxy(name, srv_class)


def _object_handles(get_handle, names):
    """Handles of the objects named by the parameters; ValueError names a bad parameter."""
    handles = {}
    for key, name in names.items():
        handle = get_handle(name).handle if isinstance(name, str) and name else -1
        if handle < 0:
            raise ValueError(f"parameter '~{key}': the scene has no object {name!r}")
        handles[key] = handle
    return handles


def wheel_command(left_handle, right_handle, speeds) -> JointSetStateData:
    msg = JointSetStateData()
    msg.handles.data = [left_handle, right_handle]
    msg.setModes.data = [vc.JOINT_SET_TARGET_VELOCITY] * 2
    msg.values.data = list(speeds)
    return msg


def read_object_names():
    names = {key: rospy.get_param("~" + key, default)
             for key, default in (("left_joint", model_object_name("leftJoint")),
                                  ("right_joint", model_object_name("rightJoint")),
                                  ("sensor", model_object_name("proxSensor0")))}
    rospy.loginfo("%s: %s", rospy.get_name(), ", ".join(f"{k}={v}" for k, v in names.items()))
    return names


def enable_streams(robot: BubbleRob, sensor: int, rand_id: str):
    """The proximity sensor stream (subscribed) and the wheels' set_joint_state subscriber
    stream; returns the wheels topic. RuntimeError when the simulator refuses either."""
    enable_publisher = _service(NODE_NAMESPACE + "simRosEnablePublisher", simRosEnablePublisher)
    topic = enable_publisher(topicName="proxData" + rand_id, queueSize=1,
                             streamCmd=vc.STRMCMD_READ_PROXIMITY_SENSOR, auxInt1=sensor,
                             auxInt2=0, auxString="").effectiveTopicName
    if not topic:
        raise RuntimeError("the simulator could not enable the proximity sensor stream")
    robot.subscribers.append(rospy.Subscriber(NODE_NAMESPACE + topic, ProximitySensorData,
                                              robot.on_sensor, queue_size=1))
    enable_subscriber = _service(NODE_NAMESPACE + "simRosEnableSubscriber", simRosEnableSubscriber)
    wheels_topic = rospy.get_name() + "/wheels"
    subscriber_id = enable_subscriber(topicName=wheels_topic, queueSize=1,
                                      streamCmd=vc.STRMCMD_SET_JOINT_STATE, auxInt1=0, auxInt2=0,
                                      auxString="").subscriberID
    if subscriber_id == -1:
        raise RuntimeError(f"the simulator could not subscribe to {wheels_topic}")
    rospy.loginfo("driving: sensor stream /vrep/%s, wheels on %s (subscriber %d)", topic,
                  wheels_topic, subscriber_id)
    return wheels_topic


def drive(robot: BubbleRob, wheels, left: int, right: int):
    """rosBubbleRob's control loop, until the simulation stops."""
    drive_back_start_s = -99.0
    while not rospy.is_shutdown() and robot.simulation_running:
        if robot.simulation_time - drive_back_start_s < BACKWARD_DURATION_S:
            speeds = BACKWARD_RAD_S
        else:
            speeds = FORWARD_RAD_S
            if robot.take_trigger():
                drive_back_start_s = robot.simulation_time
        wheels.publish(wheel_command(left, right, speeds))
        time.sleep(LOOP_PERIOD_S)


def run(rand_id: str) -> int:
    get_handle = _service(NODE_NAMESPACE + "simRosGetObjectHandle", simRosGetObjectHandle)
    handles = _object_handles(get_handle, read_object_names())
    robot = BubbleRob()
    robot.subscribers.append(rospy.Subscriber(INFO_TOPIC, VrepInfo, robot.on_info,
                                              queue_size=1))
    while not rospy.is_shutdown() and not robot.simulation_running:
        time.sleep(LOOP_PERIOD_S)           # wall time: /clock stands still while stopped
    wheels_topic = enable_streams(robot, handles["sensor"], rand_id)
    wheels = rospy.Publisher(wheels_topic, JointSetStateData, queue_size=1)
    drive(robot, wheels, handles["left_joint"], handles["right_joint"])
    rospy.loginfo("the simulation stopped: %s ends", rospy.get_name())
    for sub in robot.subscribers:
        sub.unregister()
    return 0


def main():
    rand_id = str(((int(time.time() * 1000) & 0xFFFFFF) + os.getpid()))
    rospy.init_node("vrep_example_client" + rand_id)
    try:
        return run(rand_id)
    except rospy.ROSInterruptException:
        return 0
    except (rospy.ROSException, rospy.ServiceException, RuntimeError, ValueError) as e:
        rospy.logfatal("vrep_example_client: %s", e)
        return 2
