"""The ``simRos*`` services of ``/vrep``: every service V-REP 3.3.0's legacy ROS plugin
advertises (96: all of ``vrep_common``'s srv files but ``simRosAppendStringSignal``).

Each call runs under the simulation lock (the core is not thread-safe); only work that touches
no simulation state (reading a model file) runs before it, so no request holds the lock long.
A failure never reaches rospy: it becomes V-REP's failure answer (-1 result or handle, empty
arrays and strings), its reason goes to the error log read by ``simRosGetLastErrors`` and to a
throttled warning, and the node keeps running. Services for things this simulator does not have
(dialogs, UIs, consoles, scripts, files, ...) answer the same way, so old clients get an answer
instead of hanging. The handlers live in ``services_objects``, ``services_devices`` and
``services_sim``; the four stream services call :class:`VrepStreams`.
"""
import rospy
import vrep_common.srv

from epuck_vrep_compat.compat.topics import NODE, NODE_NAMESPACE
from epuck_vrep_compat.ros.common.log import ThrottledLog
from epuck_vrep_compat.ros.vrep_plugin import services_devices, services_objects, services_sim
from epuck_vrep_compat.ros.vrep_plugin.services_objects import Prepared
from epuck_vrep_compat.vrep.backend import VrepError

NOT_ADVERTISED = ("simRosAppendStringSignal",)    # defined in vrep_common, never advertised

# Services for features this simulator does not have: "(no <what>)" in the error.
UNSUPPORTED = {
    "simRosAuxiliaryConsoleOpen": "auxiliary consoles",
    "simRosAuxiliaryConsoleClose": "auxiliary consoles",
    "simRosAuxiliaryConsolePrint": "auxiliary consoles",
    "simRosAuxiliaryConsoleShow": "auxiliary consoles",
    "simRosBreakForceSensor": "force sensors",
    "simRosCallScriptFunction": "scripts",
    "simRosCloseScene": "scene switching",
    "simRosLoadScene": "scene switching",
    "simRosCreateDummy": "dummy creation",
    "simRosDisplayDialog": "dialogs",
    "simRosEndDialog": "dialogs",
    "simRosGetDialogInput": "dialogs",
    "simRosGetDialogResult": "dialogs",
    "simRosEraseFile": "file transfer",
    "simRosTransferFile": "file transfer",
    "simRosGetCollectionHandle": "collections",
    "simRosGetCollisionHandle": "collision objects",
    "simRosGetDistanceHandle": "distance objects",
    "simRosGetJointMatrix": "joint matrices",
    "simRosSetSphericalJointMatrix": "spherical joints",
    "simRosGetModelProperty": "model properties",
    "simRosSetModelProperty": "model properties",
    "simRosSetObjectParent": "re-parenting of objects",
    "simRosSetVisionSensorImage": "writable vision sensor images",
    "simRosGetUIButtonProperty": "custom UIs",
    "simRosGetUIEventButton": "custom UIs",
    "simRosGetUIHandle": "custom UIs",
    "simRosGetUISlider": "custom UIs",
    "simRosLoadUI": "custom UIs",
    "simRosRemoveUI": "custom UIs",
    "simRosSetUIButtonLabel": "custom UIs",
    "simRosSetUIButtonProperty": "custom UIs",
    "simRosSetUISlider": "custom UIs",
}


def advertised_names():
    """The plugin's service names, from the generated vrep_common classes."""
    names = (n for n in dir(vrep_common.srv)
             if n.startswith("simRos") and not n.endswith(("Request", "Response")))
    return sorted(n for n in names if n not in NOT_ADVERTISED)


def failure_response(response_class):
    """V-REP's failure answer: -1 in ``result`` and in every handle, or, where the response has
    neither, in its first int32 field (a boolean parameter, a property, a subscriber id); the
    rest stays empty or zero."""
    res = response_class()
    int_fields = [s for s, t in zip(res.__slots__, res._slot_types) if t == "int32"]
    marked = [s for s in int_fields
              if s in ("result", "detectedObject") or s.lower().endswith("handle")]
    for field in marked or int_fields[:1]:
        setattr(res, field, -1)
    return res


def _refuse(reason):
    def handler(backend, req, errors):
        raise VrepError(reason)
    return handler


class VrepServices:
    """The plugin's ``/vrep/simRos*`` services, each answering as V-REP did (see the module's
    docstring); ``streams``: the :class:`VrepStreams` the four stream services act on."""

    def __init__(self, backend, lock, streams):
        self.backend = backend
        self._lock = lock
        self._log = ThrottledLog()              # one line per service and period
        handlers = {}
        for module in (services_objects, services_devices, services_sim):
            handlers.update(module.HANDLERS)
        handlers.update(self._stream_handlers(streams))
        self._services = []
        for name in advertised_names():
            handler = handlers.get(name)
            if handler is None:
                what = UNSUPPORTED.get(name, "such feature")
                handler = _refuse(f"{name} is not supported by this simulator (no {what})")
            service_class = getattr(vrep_common.srv, name)
            self._services.append(rospy.Service(
                "~" + name, service_class, self._wrap(name, handler,
                                                      service_class._response_class)))
        rospy.loginfo("%s: %d simRos* services advertised", NODE, len(self._services))

    @staticmethod
    def _stream_handlers(streams):
        return {
            "simRosEnablePublisher": lambda b, req, errors: streams.enable_publisher(req),
            "simRosDisablePublisher": lambda b, req, errors: streams.disable_publisher(req),
            "simRosEnableSubscriber": lambda b, req, errors: streams.enable_subscriber(req),
            "simRosDisableSubscriber": lambda b, req, errors: streams.disable_subscriber(req),
        }

    def _wrap(self, name, handler, response_class):
        def serve(req):
            errors = []
            log = self._log.warn
            try:
                if isinstance(handler, Prepared):      # the slow half outside the lock
                    prepared = handler.prepare(self.backend, req)
                    with self._lock:
                        response = handler.handler(self.backend, req, errors, prepared)
                else:
                    with self._lock:
                        response = handler(self.backend, req, errors)
            except VrepError as e:
                errors.append(str(e))
                response = failure_response(response_class)
            except Exception as e:      # a bug must not take the node (or the client) down
                errors.append(f"internal error: {type(e).__name__}: {e}")
                log = self._log.error
                response = failure_response(response_class)
            self._report(name, errors, log)
            return response
        return serve

    def _report(self, name, errors, log):
        """Every reason into the error log; the last one logged, throttled per service."""
        for reason in errors:
            self.backend.errors.add(reason if reason.startswith(name) else f"{name}: {reason}")
        if errors:
            log(name, NODE_NAMESPACE + "%s: %s", name, errors[-1])
