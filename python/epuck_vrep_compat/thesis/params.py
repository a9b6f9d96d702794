"""Private parameters of the thesis's nodes: read once at start-up, validated.

An unusable value raises :class:`ParamError` naming the parameter; the node then exits with
code 2 (see :func:`epuck_vrep_compat.thesis.vrep_client.run_node`). The validators are the
package's one set, in :mod:`epuck_vrep_compat.ros.common.params`.
"""
from epuck_vrep_compat.ros.common.params import (  # noqa: F401 (this module's interface)
    ParamError, read_float, read_name, read_names)

DEFAULT_RATE_HZ = 20.0


def read_rate_hz() -> float:
    return read_float("rate", DEFAULT_RATE_HZ)
