"""``simRos*`` handlers for the simulation, signals, parameters and the error log
(VP ``ROS_server.cpp``).

Same handler shape as :mod:`services_objects`: ``handler(backend, req, errors)``. A signal
that does not exist is not an error in V-REP (clients poll for them): it answers 0 (integer,
float) or -1 (string) without an entry in simRosGetLastErrors.
"""
import rospy
from vrep_common import srv

from epuck_vrep_compat.ros.vrep_plugin.services_objects import frame_seq, sim_stamp
from epuck_vrep_compat.vrep.backend import VrepError

ARRAY_PARAMETER_SIZE = 3


# --- simulation -----------------------------------------------------------------------------
def start_simulation(backend, req, errors):
    return srv.simRosStartSimulationResponse(result=backend.control.start())


def stop_simulation(backend, req, errors):
    return srv.simRosStopSimulationResponse(result=backend.control.stop())


def pause_simulation(backend, req, errors):
    return srv.simRosPauseSimulationResponse(result=backend.control.pause())


def synchronous(backend, req, errors):
    return srv.simRosSynchronousResponse(result=backend.control.set_synchronous(req.enable))


def synchronous_trigger(backend, req, errors):
    result = backend.control.trigger()
    if result < 0:
        errors.append("synchronous mode is off (enable it with simRosSynchronous)")
    return srv.simRosSynchronousTriggerResponse(result=result)


def get_info(backend, req, errors):
    """The values of /vrep/info."""
    _frame_id, state, sim_time, step = backend.info()
    res = srv.simRosGetInfoResponse(simulatorState=state, simulationTime=sim_time,
                                    timeStep=step)
    res.headerInfo.seq = frame_seq(backend)
    res.headerInfo.stamp = sim_stamp(backend)
    return res


def add_statusbar_message(backend, req, errors):
    rospy.loginfo("status bar: %s", req.message)
    return srv.simRosAddStatusbarMessageResponse(result=1)


def get_last_errors(backend, req, errors):
    """simxGetLastErrors: every recorded error, each followed by a NUL; the log is emptied."""
    taken = backend.errors.take()
    return srv.simRosGetLastErrorsResponse(errorCnt=len(taken),
                                           errorStrings="".join(e + "\0" for e in taken))


# --- signals --------------------------------------------------------------------------------
def _as_ros_string(value):
    """String signals are byte buffers in V-REP (a set_twist_command stream stores packed
    floats); a ROS ``string`` field is text, so bytes are passed through as latin-1 text."""
    return value.decode("latin-1") if isinstance(value, bytes) else value


def _signal_getter(kind, response_class, missing_result):
    def handler(backend, req, errors):
        try:
            value = backend.signal(kind, req.signalName)
            return response_class(result=1, signalValue=_as_ros_string(value))
        except VrepError:
            return response_class(result=missing_result)
    return handler


def get_and_clear_string_signal(backend, req, errors):
    try:
        value = backend.signal("string", req.signalName)
    except VrepError:
        return srv.simRosGetAndClearStringSignalResponse(result=-1)
    backend.clear_signal("string", req.signalName)
    return srv.simRosGetAndClearStringSignalResponse(result=1, signalValue=_as_ros_string(value))


def _signal_setter(kind, response_class):
    def handler(backend, req, errors):
        backend.set_signal(kind, req.signalName, req.signalValue)
        return response_class(result=1)
    return handler


def _signal_clearer(kind, response_class):
    """An empty name clears every signal of the kind; the result is how many were cleared."""
    def handler(backend, req, errors):
        return response_class(result=backend.clear_signal(kind, req.signalName or None))
    return handler


# --- parameters -----------------------------------------------------------------------------
def get_boolean_parameter(backend, req, errors):
    value = backend.boolean_parameter(req.parameter)
    return srv.simRosGetBooleanParameterResponse(parameterValue=int(bool(value)))


def set_boolean_parameter(backend, req, errors):
    backend.set_boolean_parameter(req.parameter, bool(req.parameterValue))
    return srv.simRosSetBooleanParameterResponse(result=1)


def get_integer_parameter(backend, req, errors):
    value = backend.integer_parameter(req.parameter)
    return srv.simRosGetIntegerParameterResponse(result=1, parameterValue=int(value))


def set_integer_parameter(backend, req, errors):
    backend.integer_parameter(req.parameter)     # an unknown parameter is reported as such
    raise VrepError(f"integer parameter {req.parameter} cannot be set in this simulator")


def get_floating_parameter(backend, req, errors):
    value = backend.floating_parameter(req.parameter)
    return srv.simRosGetFloatingParameterResponse(result=1, parameterValue=float(value))


def set_floating_parameter(backend, req, errors):
    backend.set_floating_parameter(req.parameter, float(req.parameterValue))
    return srv.simRosSetFloatingParameterResponse(result=1)


def get_array_parameter(backend, req, errors):
    values = [float(v) for v in backend.array_parameter(req.parameter)]
    return srv.simRosGetArrayParameterResponse(result=1, parameterValues=values)


def set_array_parameter(backend, req, errors):
    if len(req.parameterValues) < ARRAY_PARAMETER_SIZE:
        raise VrepError(f"array parameter {req.parameter} needs {ARRAY_PARAMETER_SIZE} values, "
                        f"got {len(req.parameterValues)}")
    backend.array_parameter(req.parameter)
    raise VrepError(f"array parameter {req.parameter} cannot be set in this simulator")


def get_string_parameter(backend, req, errors):
    value = backend.string_parameter(req.parameter)
    return srv.simRosGetStringParameterResponse(result=1, parameterValue=value)


HANDLERS = {
    "simRosStartSimulation": start_simulation,
    "simRosStopSimulation": stop_simulation,
    "simRosPauseSimulation": pause_simulation,
    "simRosSynchronous": synchronous,
    "simRosSynchronousTrigger": synchronous_trigger,
    "simRosGetInfo": get_info,
    "simRosAddStatusbarMessage": add_statusbar_message,
    "simRosGetLastErrors": get_last_errors,
    "simRosGetIntegerSignal": _signal_getter("int", srv.simRosGetIntegerSignalResponse, 0),
    "simRosGetFloatSignal": _signal_getter("float", srv.simRosGetFloatSignalResponse, 0),
    "simRosGetStringSignal": _signal_getter("string", srv.simRosGetStringSignalResponse, -1),
    "simRosGetAndClearStringSignal": get_and_clear_string_signal,
    "simRosSetIntegerSignal": _signal_setter("int", srv.simRosSetIntegerSignalResponse),
    "simRosSetFloatSignal": _signal_setter("float", srv.simRosSetFloatSignalResponse),
    "simRosSetStringSignal": _signal_setter("string", srv.simRosSetStringSignalResponse),
    "simRosClearIntegerSignal": _signal_clearer("int", srv.simRosClearIntegerSignalResponse),
    "simRosClearFloatSignal": _signal_clearer("float", srv.simRosClearFloatSignalResponse),
    "simRosClearStringSignal": _signal_clearer("string", srv.simRosClearStringSignalResponse),
    "simRosGetBooleanParameter": get_boolean_parameter,
    "simRosSetBooleanParameter": set_boolean_parameter,
    "simRosGetIntegerParameter": get_integer_parameter,
    "simRosSetIntegerParameter": set_integer_parameter,
    "simRosGetFloatingParameter": get_floating_parameter,
    "simRosSetFloatingParameter": set_floating_parameter,
    "simRosGetArrayParameter": get_array_parameter,
    "simRosSetArrayParameter": set_array_parameter,
    "simRosGetStringParameter": get_string_parameter,
}
