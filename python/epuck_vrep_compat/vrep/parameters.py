"""V-REP's simulation, object and vision parameters that our simulator really has.

A part of :class:`~epuck_vrep_compat.vrep.backend.VrepBackend`: it holds the real-time flag,
reads the simulation and its control, and resolves objects through the objects part. Anything
else raises :class:`VrepError` ("not supported"), which the services answer with V-REP's
failure value.
"""
import math

from epuck_vrep_compat.compat import vrep_codes as vc
from epuck_vrep_compat.sim.control import STOPPED
from epuck_vrep_compat.vrep.errors import VrepError


class VrepParameters:
    """The simulation, object and vision parameters V-REP's API reads and sets."""

    def __init__(self, objects, control, real_time: bool):
        """``objects``: the :class:`~epuck_vrep_compat.vrep.objects.VrepObjects` part."""
        self.objects = objects
        self.sim = objects.sim
        self.control = control
        self.real_time = real_time

    def boolean_parameter(self, parameter: int) -> bool:
        if parameter == vc.BOOLPARAM_REALTIME_SIMULATION:
            return self.real_time
        if parameter == vc.BOOLPARAM_WAITING_FOR_TRIGGER:
            return self.control.waiting_for_trigger
        raise VrepError(f"boolean parameter {parameter} is not supported by this simulator")

    def set_boolean_parameter(self, parameter: int, value: bool):
        if parameter == vc.BOOLPARAM_REALTIME_SIMULATION:
            self.real_time = bool(value)
            return
        raise VrepError(f"boolean parameter {parameter} cannot be set in this simulator")

    def floating_parameter(self, parameter: int) -> float:
        if parameter == vc.FLOATPARAM_SIMULATION_TIME_STEP:
            return self.sim.step_s
        raise VrepError(f"floating parameter {parameter} is not supported by this simulator")

    def set_floating_parameter(self, parameter: int, value: float):
        if parameter == vc.FLOATPARAM_SIMULATION_TIME_STEP:
            if not (math.isfinite(value) and 0.0 < value <= 1.0):
                raise VrepError(f"time step {value} must be in (0, 1] s")
            if self.control.state != STOPPED:
                raise VrepError("the time step can only be changed while the simulation is "
                                "stopped (as in V-REP)")
            self.sim.step_s = float(value)
            return
        raise VrepError(f"floating parameter {parameter} cannot be set in this simulator")

    def integer_parameter(self, parameter: int) -> int:
        if parameter == vc.INTPARAM_PROGRAM_VERSION:
            return vc.PROGRAM_VERSION
        if parameter == vc.INTPARAM_EDIT_MODE_TYPE:
            return 0
        raise VrepError(f"integer parameter {parameter} is not supported by this simulator")

    def array_parameter(self, parameter: int):
        if parameter == vc.ARRAYPARAM_GRAVITY:
            return [0.0, 0.0, -self.sim.epucks.model.gravity_m_s2]
        raise VrepError(f"array parameter {parameter} is not supported by this simulator")

    def string_parameter(self, parameter: int) -> str:
        if parameter == vc.STRINGPARAM_SCENE_PATH_AND_NAME:
            return self.sim.scene.source or ""
        raise VrepError(f"string parameter {parameter} is not supported by this simulator")

    def object_float_parameter(self, handle: int, parameter: int) -> float:
        obj = self.objects.get(handle)
        vision = obj.properties.get("vision")
        if vision is not None:
            spec = vision.spec
            values = {vc.VISIONFLOATPARAM_NEAR_CLIPPING: spec.near_m,
                      vc.VISIONFLOATPARAM_FAR_CLIPPING: spec.far_m,
                      vc.VISIONFLOATPARAM_PERSPECTIVE_ANGLE: _perspective_angle(spec)}
            if parameter in values:
                return values[parameter]
        if parameter == vc.JOINTFLOATPARAM_VELOCITY and "joint" in obj.properties:
            return obj.properties["joint"].velocity()
        raise VrepError(f"float parameter {parameter} of object {handle} is not supported")

    def object_int_parameter(self, handle: int, parameter: int) -> int:
        obj = self.objects.get(handle)
        vision = obj.properties.get("vision")
        if vision is not None and parameter in (vc.VISIONINTPARAM_RESOLUTION_X,
                                                vc.VISIONINTPARAM_RESOLUTION_Y):
            return vision.resolution[parameter - vc.VISIONINTPARAM_RESOLUTION_X]
        raise VrepError(f"int parameter {parameter} of object {handle} is not supported")


def _perspective_angle(spec) -> float:
    """V-REP's perspective angle is the field of view of the image's larger side."""
    if spec.width <= spec.height:
        return spec.vertical_fov_rad
    return 2.0 * math.atan(math.tan(0.5 * spec.vertical_fov_rad) * spec.width / spec.height)
