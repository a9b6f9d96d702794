"""[/proxSensors] (thesis section 4.3.1): the eleven proximity sensors on the IRB 140.

Every cycle ONE simRosGetObjectGroupData call (object type proximity sensor, data type 13)
reads every proximity sensor of the scene: per sensor two ints (detection state, detected
object's handle) and six floats (detected point x, y, z and surface normal, in the sensor's
frame). Group data returns every sensor of the scene (V-REP 3.2.1 behaviour), so the IRB's are
picked by name: their handles come once from the same call with data type 0 (names).
Published as vett_proxData on /prox_data, one proxData per name of ``~sensor_names``, in that
order; a sensor the scene does not have keeps its entry with state -1 and object handle -1.

Parameters: ``~sensor_names`` (Proximity_sensor10 .. Proximity_sensor20), ``~rate`` (20 Hz).
"""
from typing import Dict, List, Optional, Sequence, Tuple

import rospy
from vrep_common.srv import simRosGetObjectGroupData

from epuck_vrep_compat.compat import vrep_codes as vc
from epuck_vrep_compat.compat.thesis_names import PROX_NODE, PROX_SENSOR_NAMES, PROX_TOPIC
from epuck_vrep_compat.msg import proxData, vett_proxData
from epuck_vrep_compat.thesis import params
from epuck_vrep_compat.thesis.vrep_client import VrepClient, run_node, spin_periodic

INTS, FLOATS = 2, 6             # per object in data type 13
NOT_READ = ((-1, -1), (0.0,) * FLOATS)


def sensor_handles(wanted: Sequence[str], names: Dict[int, str]) -> List[Tuple[str, int]]:
    """(name, handle) for each wanted sensor name; handle -1 when the scene has none."""
    by_name = {name: handle for handle, name in names.items()}
    return [(name, by_name.get(name, -1)) for name in wanted]


def readings_by_handle(handles: Sequence[int], ints: Sequence[int],
                       floats: Sequence[float]) -> Dict[int, Tuple[Sequence[int], Sequence[float]]]:
    """{handle: (ints, floats)} of a data type 13 answer; {} when its arrays do not fit."""
    if len(ints) != INTS * len(handles) or len(floats) != FLOATS * len(handles):
        return {}
    return {h: (ints[INTS * k:INTS * (k + 1)], floats[FLOATS * k:FLOATS * (k + 1)])
            for k, h in enumerate(handles)}


def prox_message(sensors: Sequence[Tuple[str, int]], readings) -> vett_proxData:
    """One proxData per sensor, in order; a sensor without a reading gets state -1."""
    out = []
    for name, handle in sensors:
        (state, detected), floats = readings.get(handle, NOT_READ)
        out.append(proxData(state=state, objectHandle=detected, nomeProx=name,
                            point=list(floats[:3]), normal=list(floats[3:])))
    return vett_proxData(proxData=out)


class ProxSensors:
    """The proxSensors node: the IRB 140's proximity sensors from one group-data call."""

    def __init__(self):
        self.sensor_names = params.read_names("sensor_names", PROX_SENSOR_NAMES,
                                              exact_count=False)
        self.rate_hz = params.read_rate_hz()
        self.client = VrepClient({"simRosGetObjectGroupData": simRosGetObjectGroupData})
        # 10 messages = 0.5 s at 20 Hz for a slow subscriber (rosbag), never blocking the loop
        self._pub = rospy.Publisher(PROX_TOPIC, vett_proxData, queue_size=10)
        self._sensors: Optional[List[Tuple[str, int]]] = None
        rospy.loginfo("%s: %d sensors (%s .. %s) -> %s, rate %.1f Hz", rospy.get_name(),
                      len(self.sensor_names), self.sensor_names[0], self.sensor_names[-1],
                      PROX_TOPIC, self.rate_hz)

    def _look_up_sensors(self) -> bool:
        names = self.client.object_names(vc.OBJECT_PROXIMITY_SENSOR)
        if names is None:
            return False
        self._sensors = sensor_handles(self.sensor_names, names)
        missing = [name for name, handle in self._sensors if handle < 0]
        if missing:
            self.client.log.warn("missing", "%s: the scene has no proximity sensor named %s: "
                                 "state -1 in %s", rospy.get_name(),
                                 ", ".join(f"'{n}'" for n in missing), PROX_TOPIC)
        return True

    def step(self):
        if self._sensors is None and not self._look_up_sensors():
            return
        res = self.client.group_data(vc.OBJECT_PROXIMITY_SENSOR, vc.GROUP_DATA_PROXIMITY)
        if res is None:
            return
        readings = readings_by_handle(res.handles, res.intData, res.floatData)
        if not readings and res.handles:
            self.client.log.warn("sizes", "%s: group data 13 answered %d handles, %d ints, %d "
                                 "floats: not 2 and 6 per sensor", rospy.get_name(),
                                 len(res.handles), len(res.intData), len(res.floatData))
        self._pub.publish(prox_message(self._sensors, readings))
        if any(handle >= 0 and handle not in readings for _, handle in self._sensors):
            self._sensors = None            # a sensor vanished (another scene?): look up again

    def run(self):
        spin_periodic(self.rate_hz, self.step)


def main() -> int:
    return run_node(PROX_NODE, ProxSensors)
