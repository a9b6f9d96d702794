"""The streams of the ``/vrep`` face: publishers and subscribers enabled at run time through
``simRosEnablePublisher`` / ``simRosEnableSubscriber``, as V-REP 3.3.0's legacy ROS plugin
(``ROS_server::addPublisher``, ``removePublisher``, ``addSubscriber``, ``removeSubscriber``,
``streamAllData``, ``simulationEnded``).

* Streams can be enabled only while the simulation runs, and all end when it stops.
* Publisher streams are reference counted by identity (command + its aux arguments) and publish
  once per simulation step through the node's :class:`StepBatch`; one whose target disappears
  ends. get_transform streams have no topic: their transforms go out together on ``/tf``.
* Subscriber streams get IDs counting up from 0 (the plugin's ``lastSubscriberID``, never reset)
  and act on the simulation from rospy's threads, under the simulation lock.
* Each table holds at most :data:`MAX_STREAMS` streams (V-REP had no bound); enabling one more
  fails as any refused enable does, with the reason in the error log.
Callers of the enable/disable methods and of :meth:`VrepStreams.publish` hold the lock. No
method raises: failures return V-REP's failure value and are recorded for simRosGetLastErrors.
What each command does is in :mod:`stream_publishers`, :mod:`stream_sensors` and
:mod:`stream_subscribers`; the naming rules in :mod:`stream_names`.
"""
from dataclasses import dataclass

import rospy
from tf2_msgs.msg import TFMessage
from vrep_common.srv import (
    simRosDisablePublisherResponse, simRosDisableSubscriberResponse,
    simRosEnablePublisherResponse, simRosEnableSubscriberResponse)

from epuck_vrep_compat.compat.topics import TF_TOPIC
from epuck_vrep_compat.ros.common.log import ThrottledLog
from epuck_vrep_compat.ros.vrep_plugin.stream_names import (
    Aux, FrameNames, resolve_topic, sanitize, stream_identity, unique_topic_name)
from epuck_vrep_compat.ros.vrep_plugin.stream_publishers import (
    GENERAL_PUBLISHERS, PublisherKind, StreamStep)
from epuck_vrep_compat.ros.vrep_plugin.stream_sensors import SENSOR_PUBLISHERS
from epuck_vrep_compat.ros.vrep_plugin.stream_subscribers import (
    InvalidMessage, SubscriberKind, subscriber_kinds)
from epuck_vrep_compat.ros.vrep_plugin.stream_wiring import RospyWiring
from epuck_vrep_compat.vrep.backend import VrepError

PUBLISHER_KINDS = {**GENERAL_PUBLISHERS, **SENSOR_PUBLISHERS}
ENABLE_PUBLISHER, ENABLE_SUBSCRIBER = "simRosEnablePublisher", "simRosEnableSubscriber"
MAX_STREAMS = 1000          # publisher streams, and subscriber streams, enabled at once
FULL = "the stream table is full: {} {} streams are enabled; disable one first"


@dataclass
class _PublisherStream:
    name: str                   # effective topic name, as the client got it
    identity: tuple
    kind: PublisherKind
    aux: Aux
    publisher: object           # None: get_transform (sent on /tf)
    references: int = 1


@dataclass
class _SubscriberStream:
    subscriber_id: int
    kind: SubscriberKind
    aux: Aux
    subscriber: object = None
    active: bool = True


class VrepStreams:
    """The plugin's streams: publisher streams published once per step, subscriber streams
    acting on the simulation (see the module's docstring); ``wiring``: the rospy side
    (:class:`RospyWiring` unless a test replaces it)."""

    def __init__(self, backend, lock, wiring=None):
        self.backend = backend
        self.lock = lock
        self._wiring = wiring if wiring is not None else RospyWiring()
        self._frames = FrameNames()
        self._publishers = {}             # effective name -> stream, in creation order
        self._subscribers = {}            # subscriber ID -> stream
        self._next_subscriber_id = 0
        self._tf = None                   # /tf publisher while get_transform streams exist
        self._subscriber_kinds = subscriber_kinds(self._status_bar)
        self._log = ThrottledLog()

    # --- publishers -----------------------------------------------------------------------
    def enable_publisher(self, req) -> simRosEnablePublisherResponse:
        return simRosEnablePublisherResponse(self._add_publisher(req))

    def _add_publisher(self, req) -> str:
        if not self.backend.running:
            return self._fail("", ENABLE_PUBLISHER, "the simulation is not running")
        if not req.topicName:
            return self._fail("", ENABLE_PUBLISHER, "Invalid topic name.")
        aux = Aux(req.auxInt1, req.auxInt2, req.auxString)
        kind = PUBLISHER_KINDS.get(req.streamCmd)
        if kind is None:
            return self._fail("", ENABLE_PUBLISHER, f"Topic could not be published. (stream "
                                  f"command {req.streamCmd} is not a supported publisher command)")
        identity = stream_identity(req.streamCmd, aux)
        for stream in self._publishers.values():
            if stream.identity == identity:
                stream.references += 1
                return stream.name
        if len(self._publishers) >= MAX_STREAMS:
            return self._fail("", ENABLE_PUBLISHER, "Topic could not be published. (" +
                              FULL.format(MAX_STREAMS, "publisher") + ")")
        try:
            if kind.check is not None:
                kind.check(self.backend, aux)
        except VrepError as e:
            return self._fail("", ENABLE_PUBLISHER,
                              f"Topic could not be published. ({kind.name}: {e})")
        name = unique_topic_name(req.topicName, self._publication_taken)
        if not self._wiring.is_legal(resolve_topic(name)):
            return self._fail("", ENABLE_PUBLISHER, f"Invalid topic name. ('{req.topicName}')")
        publisher = None
        if kind.msg_class is not None:
            publisher = self._wiring.advertise(resolve_topic(name), kind.msg_class)
        elif self._tf is None:
            self._tf = self._wiring.advertise(TF_TOPIC, TFMessage)
        self._publishers[name] = _PublisherStream(name, identity, kind, aux, publisher)
        rospy.loginfo("stream %s on '%s' enabled", kind.name, name)
        return name

    def _publication_taken(self, resolved: str) -> bool:
        return any(resolve_topic(name) == resolved for name in self._publishers) or \
            self._wiring.publication_exists(resolved)

    def disable_publisher(self, req) -> simRosDisablePublisherResponse:
        stream = self._publishers.get(req.topicName)
        if stream is None:
            return simRosDisablePublisherResponse(self._fail(
                -1, "simRosDisablePublisher",
                f"Topic could not be unpublished. ('{req.topicName}' is not enabled)"))
        stream.references -= 1
        if stream.references > 0:
            return simRosDisablePublisherResponse(stream.references)
        self._remove_publisher(stream)
        rospy.loginfo("stream %s on '%s' disabled", stream.kind.name, stream.name)
        return simRosDisablePublisherResponse(0)

    def _remove_publisher(self, stream: _PublisherStream):
        del self._publishers[stream.name]
        if stream.publisher is not None:
            stream.publisher.unregister()
        if self._tf is not None and all(s.publisher is not None
                                        for s in self._publishers.values()):
            self._tf.unregister()
            self._tf = None

    def publish(self, batch, secs: int, nsecs: int, send_transforms=None):
        """One simulation step: every publisher stream, in the order they were enabled;
        ``send_transforms(msg)`` takes the get_transform streams' TFMessage (by default it goes
        into the batch on ``/tf`` at once)."""
        if not self._publishers:
            return
        step = StreamStep(self.backend, self._frames, secs, nsecs)
        transforms = []
        for stream in list(self._publishers.values()):
            try:
                msg = self._build(stream, step, batch)
            except Exception as e:  # noqa: BLE001 - one stream's failure must not stop the step
                self._remove_publisher(stream)
                self._warn(f"stream {stream.kind.name} on '{stream.name}' ended: {e}")
                continue
            if msg is None:
                continue
            if stream.publisher is None:
                transforms.append(msg)
            else:
                batch.add(stream.publisher, msg)
        if not transforms:
            return
        if send_transforms is None:
            batch.add(self._tf, TFMessage(transforms))
        else:
            send_transforms(TFMessage(transforms))

    def _build(self, stream: _PublisherStream, step: StreamStep, batch):
        kind = stream.kind
        wanted = batch.wanted(stream.publisher if stream.publisher is not None else self._tf)
        if not wanted and not kind.always and kind.probe is not None:
            kind.probe(self.backend, stream.aux)        # costly to build: only see it is alive
            return None
        return kind.build(step, stream.aux)

    # --- subscribers ----------------------------------------------------------------------
    def enable_subscriber(self, req) -> simRosEnableSubscriberResponse:
        return simRosEnableSubscriberResponse(self._add_subscriber(req))

    def _add_subscriber(self, req) -> int:
        if not self.backend.running:
            return self._fail(-1, ENABLE_SUBSCRIBER, "the simulation is not running")
        if not req.topicName:
            return self._fail(-1, ENABLE_SUBSCRIBER, "Invalid topic name.")
        aux = Aux(req.auxInt1, req.auxInt2, req.auxString)
        kind = self._subscriber_kinds.get(req.streamCmd)
        if kind is None:
            return self._fail(-1, ENABLE_SUBSCRIBER, f"Topic could not be subscribed. (stream "
                                  f"command {req.streamCmd} is not a supported subscriber command)")
        if len(self._subscribers) >= MAX_STREAMS:
            return self._fail(-1, ENABLE_SUBSCRIBER, "Topic could not be subscribed. (" +
                              FULL.format(MAX_STREAMS, "subscriber") + ")")
        try:
            if kind.check is not None:
                kind.check(self.backend, aux)
        except VrepError as e:
            return self._fail(-1, ENABLE_SUBSCRIBER,
                              f"Topic could not be subscribed. ({kind.name}: {e})")
        resolved = resolve_topic(sanitize(req.topicName))
        if not self._wiring.is_legal(resolved):
            return self._fail(-1, ENABLE_SUBSCRIBER, f"Invalid topic name. ('{req.topicName}')")
        existing_type = self._wiring.subscription_type(resolved)
        if existing_type not in (None, kind.msg_class._type):
            return self._fail(-1, ENABLE_SUBSCRIBER, f"Topic could not be subscribed. "
                                  f"('{resolved}' is already subscribed as {existing_type})")
        stream = _SubscriberStream(self._next_subscriber_id, kind, aux)
        self._next_subscriber_id += 1
        # roscpp's queue size 0 means unbounded, as rospy's None
        queue_size = req.queueSize if req.queueSize > 0 else None
        stream.subscriber = self._wiring.subscribe(resolved, kind.msg_class, self._on_message,
                                                   stream, queue_size)
        self._subscribers[stream.subscriber_id] = stream
        rospy.loginfo("stream %s from '%s' enabled (subscriber %d)", kind.name, resolved,
                      stream.subscriber_id)
        return stream.subscriber_id

    def disable_subscriber(self, req) -> simRosDisableSubscriberResponse:
        stream = self._subscribers.pop(req.subscriberID, None)
        if stream is None:
            return simRosDisableSubscriberResponse(self._fail(
                0, "simRosDisableSubscriber",
                f"Topic could not be unsubscribed. (no subscriber {req.subscriberID})"))
        self._shut_down(stream)
        rospy.loginfo("stream %s (subscriber %d) disabled", stream.kind.name,
                      stream.subscriber_id)
        return simRosDisableSubscriberResponse(1)

    def _on_message(self, msg, stream: _SubscriberStream):
        """A subscriber stream's message (rospy thread)."""
        with self.lock:
            if not stream.active:
                return
            kind = stream.kind
            try:
                kind.apply(self.backend, stream.aux, msg)
                return
            except InvalidMessage as e:
                self._warn(f"{kind.name} (subscriber {stream.subscriber_id}): message "
                           f"ignored: {e}")
                return
            except Exception as e:  # noqa: BLE001 - a VrepError, or a bug: keep the node up
                self._warn(f"{kind.name} (subscriber {stream.subscriber_id}): {e}")
                if not kind.stop_on_error or self._target_alive(stream):
                    return
                stream.active = False       # the plugin shut such a subscriber down
        rospy.loginfo("stream %s (subscriber %d) shut down: its target is not valid",
                      kind.name, stream.subscriber_id)
        self._shut_down(stream)

    def _target_alive(self, stream: _SubscriberStream) -> bool:
        if stream.kind.check is None:
            return False
        try:
            stream.kind.check(self.backend, stream.aux)
            return True
        except VrepError:
            return False

    @staticmethod
    def _shut_down(stream: _SubscriberStream):
        stream.active = False
        subscriber, stream.subscriber = stream.subscriber, None
        if subscriber is not None:
            subscriber.unregister()

    # --- simulation end -------------------------------------------------------------------
    def remove_all(self):
        """The simulation stopped: every stream ends (the plugin's simulationEnded)."""
        with self.lock:
            for stream in list(self._publishers.values()):
                self._remove_publisher(stream)
            for stream in self._subscribers.values():
                self._shut_down(stream)
            self._subscribers.clear()
            self._frames.clear()

    # --- errors -----------------------------------------------------------------------------
    def _fail(self, value, service: str, message: str):
        """V-REP's failure value; the reason goes to simRosGetLastErrors and the log."""
        self._warn(f"{service}: {message}")
        return value

    def _warn(self, message: str):
        self.backend.errors.add(message)
        self._log.warn(message, "%s", message)

    @staticmethod
    def _status_bar(text: str):
        rospy.loginfo("[status bar] %s", text)
