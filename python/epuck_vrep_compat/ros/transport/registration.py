"""Registering many topics with the ROS master in bulk, off the thread that creates them.

rospy registers every publisher, subscriber and service with one XML-RPC call to the master,
made by the thread that creates it and waited for: a thousand robots' 15 000 topics took about
17 s of the simulator's start-up. :class:`BulkRegistration` takes those calls over while it is
active: each registration is queued in order and a background thread sends the queue to the
master in ``system.multicall`` batches (the master's XML-RPC server accepts them), so creating
a publisher costs microseconds and the simulation can step while the master learns of it.
For the same reason, while the context is active, rospy's check of ``/enable_statistics`` (one
parameter-server call per new subscriber) is answered from one read made on entry, and rospy's
registration thread stops re-checking every topic's connections twice a second under the lock
that creating a topic takes (with thousands of topics it held that lock for a third of the
start-up); dead connections are still dropped when a write to them fails, and the checks
resume on exit.

Answers are handled as rospy's ``RegManager`` does: a subscriber's current publishers are
handed to rospy, which connects to them; a refused registration is logged as fatal. While the
master is unreachable the batch is retried, like rospy. Registrations and unregistrations stay
in their order: one made after the context (a service creating a topic at run time) waits
until the queue has been sent, then goes through rospy's own synchronous path, so its caller
still finds it at the master when it returns.

It relies on rospy's ``RegManager`` (its ``reg_added``, ``reg_removed``, ``publisher_update``,
``uri`` and ``master_uri``) and on ``Registration``'s type constants, unchanged since ROS Kinetic.

Stopping is the same in reverse: :func:`withdraw_all` hands the node's registrations' reverse
(``unregisterPublisher``, ``unregisterSubscriber``, ``unregisterService``,
``unsubscribeParam``) to a process that
sends them in ``system.multicall`` batches (``withdraw.py``), and clears rospy's registration
listeners, so that rospy unregisters nothing a second time as it closes its topics.
"""
import threading
import time
import xmlrpc.client

import rospy
from rospy.impl.registration import (RegManager, Registration, get_registration_listeners,
                                     get_service_manager, get_topic_manager)
from rospy.impl.paramserver import get_param_server_cache
from rospy.impl.statistics import SubscriberStatisticsLogger

from epuck_vrep_compat.ros.common.log import ThrottledLog
from epuck_vrep_compat.ros.transport import withdraw

_REGISTER = {Registration.PUB: "registerPublisher", Registration.SUB: "registerSubscriber",
             Registration.SRV: "registerService"}
_UNREGISTER = {Registration.PUB: "unregisterPublisher", Registration.SUB: "unregisterSubscriber",
               Registration.SRV: "unregisterService"}
_RETRY_S = 0.2


def _arguments(method, reg_type, caller_id, name, type_or_uri, node_uri):
    """The master API's arguments, as rospy's ``RegManager`` passes them."""
    if method in _REGISTER.values():
        return caller_id, name, type_or_uri, node_uri
    if reg_type == Registration.SRV:
        return caller_id, name, type_or_uri          # unregisterService takes the service's URI
    return caller_id, name, node_uri


def rospy_registrar():
    """The node's rospy ``RegManager`` (present once ``init_node`` has returned), or None."""
    for listener in get_registration_listeners().listeners:
        if isinstance(listener, RegManager):
            return listener
    return None


class BulkRegistration:
    """Sends rospy's registrations with the master in batches from a background thread.

    Use as a context manager around code that creates many topics; they are registered
    in order after they were created, while the caller goes on. ``batch_size`` registrations
    go in one ``system.multicall``. ``master`` replaces the XML-RPC proxy (tests).
    """

    def __init__(self, registrar=None, batch_size: int = 500, master=None):
        self._registrar = registrar if registrar is not None else rospy_registrar()
        self._batch_size = batch_size
        self._master = master
        self._queue = []               # (method, name, type or uri, reg_type)
        self._lock = threading.Condition()
        self._deferring = False        # the caller is still inside the ``with``
        self._thread = None
        self._closed = False           # the node stops: nothing more is sent
        self._statistics_check = None  # rospy's classmethod, while replaced
        self._log = ThrottledLog()
        self.sent = 0                  # registrations the master has answered

    def __enter__(self):
        if self._registrar is not None:
            self._statistics_check = vars(SubscriberStatisticsLogger)["is_enabled"]
            statistics = bool(SubscriberStatisticsLogger.is_enabled())
            SubscriberStatisticsLogger.is_enabled = classmethod(lambda cls: statistics)
            get_topic_manager().check_all = lambda: None
            with self._lock:
                self._deferring = True
                self._registrar.reg_added = self._added
                self._registrar.reg_removed = self._removed
        return self

    def __exit__(self, *exc):
        if self._statistics_check is not None:                # rospy's own checks again
            SubscriberStatisticsLogger.is_enabled = self._statistics_check
            self._statistics_check = None
            vars(get_topic_manager()).pop("check_all", None)
        with self._lock:
            self._deferring = False
            if self._registrar is None:
                return
            if not self._queue:
                self._restore()
            else:
                self._ensure_thread()

    def wait(self, timeout_s: float = None) -> bool:
        """Block until every queued registration was answered; False on timeout."""
        if self._registrar is None:
            return True
        deadline = None if timeout_s is None else time.monotonic() + timeout_s
        with self._lock:
            while self._queue or self._deferring or self._is_intercepting():
                left = None if deadline is None else deadline - time.monotonic()
                if left is not None and left <= 0:
                    return False
                self._lock.wait(left)
        return True

    def close(self, timeout_s: float = 2.0):
        """The node stops: drop what was not sent yet (the master never learnt of it) and wait
        up to ``timeout_s`` for a batch on its way, so that :func:`withdraw_all` comes after
        every registration the master got."""
        with self._lock:
            self._closed = True
            self._queue.clear()
            self._lock.notify_all()
            thread = self._thread
        if thread is not None and thread is not threading.current_thread():
            thread.join(timeout_s)

    # --- queueing (rospy's threads, under its registration-listener lock) -----------------
    def _added(self, resolved_name, data_type_or_uri, reg_type):
        if not self._deferred(_REGISTER[reg_type], resolved_name, data_type_or_uri, reg_type):
            type(self._registrar).reg_added(self._registrar, resolved_name, data_type_or_uri,
                                            reg_type)

    def _removed(self, resolved_name, data_type_or_uri, reg_type):
        if not self._deferred(_UNREGISTER[reg_type], resolved_name, data_type_or_uri, reg_type):
            type(self._registrar).reg_removed(self._registrar, resolved_name, data_type_or_uri,
                                              reg_type)

    def _deferred(self, method, resolved_name, data_type_or_uri, reg_type) -> bool:
        """Queue it inside the context (True); after it, wait until the queue was sent and
        leave it to rospy (False)."""
        with self._lock:
            if self._closed:
                return True
            if self._deferring:
                self._queue.append((method, resolved_name, data_type_or_uri, reg_type))
                self._ensure_thread()     # sending overlaps with creating the next topics
                self._lock.notify_all()
                return True
            while self._queue and not rospy.is_shutdown():
                self._lock.wait(_RETRY_S)
            return False

    def _ensure_thread(self):
        """Start the sending thread unless it runs (holding ``self._lock``)."""
        if self._thread is None:
            self._thread = threading.Thread(target=self._run, name="bulk_registration",
                                            daemon=True)
            self._thread.start()

    def _is_intercepting(self):
        return "reg_added" in vars(self._registrar)

    def _restore(self):
        """rospy's own synchronous registration again (the queue is empty)."""
        vars(self._registrar).pop("reg_added", None)
        vars(self._registrar).pop("reg_removed", None)
        self._lock.notify_all()

    # --- the background thread --------------------------------------------------------------
    def _run(self):
        while not rospy.is_shutdown():
            with self._lock:
                if self._closed:
                    break
                if not self._queue:
                    if self._deferring:
                        self._lock.wait(_RETRY_S)
                        continue
                    break
                batch = self._queue[:self._batch_size]
            if self._send(batch):
                with self._lock:
                    del self._queue[:len(batch)]
                    self.sent += len(batch)
                    self._lock.notify_all()
            else:
                time.sleep(_RETRY_S)
        with self._lock:       # after the context nothing is queued: no registration is lost
            self._thread = None
            if self._queue and not rospy.is_shutdown() and not self._closed:
                self._ensure_thread()
            elif not self._deferring:
                self._restore()

    def _send(self, batch) -> bool:
        """One multicall; True once the master answered it (whatever each answer was)."""
        registrar = self._registrar
        master = self._master or xmlrpc.client.ServerProxy(registrar.master_uri)
        try:
            answers = withdraw.multicall(master, _calls(batch, rospy.get_caller_id(),
                                                        registrar.uri))
        except (OSError, xmlrpc.client.Error) as e:
            self._log.warn("registration", "registering %d topics with the master at %s failed "
                           "(%s); retrying", len(batch), registrar.master_uri, e)
            return False
        for (method, name, _type, _reg), (code, msg, value) in zip(batch, answers):
            if code != 1:
                rospy.logfatal("the master refused %s of [%s]: %s", method, name, msg)
            elif method == "registerSubscriber":
                registrar.publisher_update(name, value)
        return True


def _calls(batch, caller_id, node_uri):
    """The master API's calls, (method, arguments), for queued (method, name, type or uri,
    reg_type) entries."""
    return [(method, _arguments(method, reg_type, caller_id, name, type_or_uri, node_uri))
            for method, name, type_or_uri, reg_type in batch]


def withdraw_all(registrar=None) -> int:
    """Every topic, subscription and service of this node withdrawn from the master, in the
    order they were registered (the master finds each at the front of its lists), by a
    process of its own (``withdraw.py``: the master needs seconds for thousands, which the
    stopping node does not wait for), and the parameters it subscribed to (rospy's own
    cache), which rospy never unsubscribes: the master then forgets the node. rospy's
    registration listeners are cleared, so that closing a topic afterwards calls no one.
    Returns how many calls were handed over."""
    registrar = registrar if registrar is not None else rospy_registrar()
    get_registration_listeners().clear()
    if registrar is None or not registrar.master_uri:
        return 0
    topics, services = get_topic_manager(), get_service_manager()
    batch = [(_UNREGISTER[Registration.PUB], name, None, Registration.PUB)
             for name, _type in topics.get_publications()]
    batch += [(_UNREGISTER[Registration.SUB], name, None, Registration.SUB)
              for name, _type in topics.get_subscriptions()]
    batch += [(_UNREGISTER[Registration.SRV], name, uri, Registration.SRV)
              for name, uri in services.get_services()]
    calls = _calls(batch, rospy.get_caller_id(), registrar.uri)
    calls += [("unsubscribeParam", (rospy.get_caller_id(), registrar.uri, key))
              for key in _cached_params(get_param_server_cache().d)]
    if calls:
        withdraw.hand_off(registrar.master_uri, calls)
    return len(calls)


def _cached_params(tree, prefix="/"):
    """The keys of rospy's parameter cache (``get_param_cached``: each a subscription with the
    master, rospy's own ``/rosout_disable_topics_generation`` among them): the leaves of its
    tree, or the key of an empty one."""
    for key, value in (tree or {}).items():
        if isinstance(value, dict) and value:
            yield from _cached_params(value, f"{prefix}{key}/")
        else:
            yield prefix + key
