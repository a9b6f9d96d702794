"""Parameters of the drivers' extra sensors (``~epuck2/*``, ``~microphone/levels``), read once
and validated like the others (:class:`ParamError` naming the parameter)."""
import math

import rospy

from epuck_vrep_compat.ros.common.params import ParamError, read_typed as _get
from epuck_vrep_compat.epuck.epuck2_sensors import Epuck2Settings


def _finite_list(name, default, count):
    value = rospy.get_param("~" + name, list(default))
    if (not isinstance(value, (list, tuple)) or len(value) != count
            or not all(isinstance(v, (int, float)) and not isinstance(v, bool)
                       and math.isfinite(v) for v in value)):
        raise ParamError(f"parameter '~{name}' must be a list of {count} finite numbers, "
                         f"got {value!r}")
    return tuple(float(v) for v in value)


def read_extras_settings(profile) -> Epuck2Settings:
    s = Epuck2Settings()
    s.tof_stddev_m = _get("epuck2/tof_stddev_m", s.tof_stddev_m, float, lambda v: v >= 0.0,
                          "must be >= 0")
    s.tof_stddev_rel = _get("epuck2/tof_stddev_rel", s.tof_stddev_rel, float,
                            lambda v: v >= 0.0, "must be >= 0")
    s.mag_world_tesla = _finite_list("epuck2/mag_world_tesla", s.mag_world_tesla, 3)
    if math.hypot(s.mag_world_tesla[0], s.mag_world_tesla[1]) == 0.0:
        raise ParamError("parameter '~epuck2/mag_world_tesla' needs a horizontal component "
                         "(the heading and the driver's arrow come from it)")
    s.mag_stddev_tesla = _get("epuck2/mag_stddev_tesla", s.mag_stddev_tesla, float,
                              lambda v: v >= 0.0, "must be >= 0")
    s.battery_full_v = _get("epuck2/battery_full_v", s.battery_full_v, float,
                            lambda v: 3.4 <= v <= 4.2, "must be in 3.4..4.2 V")
    s.battery_discharge_s = _get("epuck2/battery_discharge_s", s.battery_discharge_s, float,
                                 lambda v: v > 0.0, "must be > 0")
    count = max(profile.microphones, 1)
    levels = _finite_list("microphone/levels", [0] * count, count)
    if any(v < 0 or v > 65535 or v != int(v) for v in levels):
        raise ParamError(f"parameter '~microphone/levels' must hold integers in 0..65535, "
                         f"got {list(levels)}")
    s.mic_levels = tuple(int(v) for v in levels)
    return s
