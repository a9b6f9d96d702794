"""What every thesis node shares: the ``/vrep`` services of V-REP's legacy ROS plugin as
persistent proxies, waiting for the simulator, throttled warnings, the periodic loop and the
node's start and exit.

The nodes talk to the simulator only through these services, as the thesis's nodes did with
V-REP (section 4.1). A persistent proxy saves a connection per call; when its connection breaks
(the simulator restarted) the call fails once, with a warning, and the next call reconnects.
"""
import threading
import time
from typing import Callable, Dict, Optional

import rospy

from epuck_vrep_compat.compat import vrep_codes as vc
from epuck_vrep_compat.compat.topics import NODE
from epuck_vrep_compat.ros.common.log import ThrottledLog
from epuck_vrep_compat.thesis.params import ParamError

FIRST_WAIT_S = 1.0          # the first "waiting for" line comes after this long
WAIT_LOG_PERIOD_S = 5.0     # then one line per period until the service is up


class VrepClient:
    """Persistent proxies to the ``/vrep/<name>`` services a node uses (``{name: srv class}``)."""

    def __init__(self, services: Dict[str, type]):
        self._classes = dict(services)
        self._proxies: Dict[str, rospy.ServiceProxy] = {}
        self._handles: Dict[str, int] = {}
        self.log = ThrottledLog()

    def wait(self) -> bool:
        """Block until every service is up, saying so every few seconds; False on shutdown."""
        for name in self._classes:
            full_name = f"{NODE}/{name}"
            timeout_s = FIRST_WAIT_S
            while True:
                try:
                    rospy.wait_for_service(full_name, timeout=timeout_s)
                    break
                except rospy.ROSInterruptException:
                    return False
                except rospy.ROSException:
                    if rospy.is_shutdown():
                        return False
                    rospy.loginfo("%s: waiting for %s (is the simulator running?)",
                                  rospy.get_name(), full_name)
                    timeout_s = WAIT_LOG_PERIOD_S
        rospy.loginfo("%s: %s is up", rospy.get_name(), NODE)
        return True

    def call(self, name: str, **request):
        """The service's response, or None after a failed call (warned, throttled)."""
        proxy = self._proxies.get(name)
        if proxy is None:
            proxy = rospy.ServiceProxy(f"{NODE}/{name}", self._classes[name],
                                       persistent=True)
            self._proxies[name] = proxy
        try:
            return proxy(**request)
        except (rospy.ServiceException, rospy.exceptions.TransportException, OSError) as e:
            proxy.close()
            del self._proxies[name]       # reconnect on the next call
            self.log.warn("call:" + name, "%s: %s/%s failed: %s", rospy.get_name(), NODE,
                          name, e)
            return None

    def group_data(self, object_type: int, data_type: int):
        """simRosGetObjectGroupData's response, or None after a failed call."""
        return self.call("simRosGetObjectGroupData", objectType=object_type, dataType=data_type)

    def object_names(self, object_type: int = vc.APPOBJ_OBJECT) -> Optional[Dict[int, str]]:
        """{handle: name} of every object of a type (all objects by default), the thesis's way:
        simRosGetObjectGroupData with data type 0; None after a failed call."""
        res = self.group_data(object_type, vc.GROUP_DATA_NAMES)
        return None if res is None else dict(zip(res.handles, res.strings))

    def handle(self, name: str, what: str = "object") -> int:
        """simRosGetObjectHandle, remembered once found; -1 (warned, throttled) while the scene
        has no such object or the call fails."""
        handle = self._handles.get(name, -1)
        if handle >= 0:
            return handle
        res = self.call("simRosGetObjectHandle", objectName=name)
        if res is not None and res.handle >= 0:
            self._handles[name] = res.handle
            return res.handle
        if res is not None:
            self.log.warn("handle:" + name, "%s: the scene has no %s named '%s'; trying again",
                          rospy.get_name(), what, name)
        return -1


    def forget_handle(self, name: str):
        """Look ``name`` up again next time (its handle stopped working: another scene)."""
        self._handles.pop(name, None)


def spin_periodic(rate_hz: float, step: Callable[[], None]):
    """Call ``step`` at ``rate_hz`` of ROS time (simulation time under /use_sim_time) until
    shutdown."""
    rate = rospy.Rate(rate_hz)
    while not rospy.is_shutdown():
        step()
        try:
            rate.sleep()
        except rospy.ROSTimeMovedBackwardsException:
            pass                        # a restarted clock: carry on from the new time


def run_node(node_name: str, make_node: Callable[[], object]) -> int:
    """Start a thesis node: ``make_node()`` reads its parameters and returns an object with a
    ``client`` (:class:`VrepClient`) and ``run()``. Exit code 2 for an unusable parameter."""
    rospy.init_node(node_name)
    try:
        node = make_node()
        if node.client.wait():
            node.run()
    except ParamError as e:
        rospy.logfatal("%s: %s", rospy.get_name(), e)
        return 2
    except rospy.ROSInterruptException:
        pass
    return 0
