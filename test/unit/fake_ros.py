"""Stand-ins for the parts of rospy a client node touches at its start, for unit tests of the
nodes' logic without a master: publishers that keep what they publish (and, latched, the last
message, as rospy's ``impl.latch``), subscribers, services and timers that keep their
callbacks, parameters from a dict, and tf2 buffers that ask the master nothing.

``install(monkeypatch, params)`` puts them in rospy (and tf2_ros) for one test and returns the
:class:`Ros` that holds what the node made: ``ros.publishers[topic]``,
``ros.subscribers[topic]``, ``ros.services[name]``. ``bench_script(name)``: one of the safety
benchmark's node scripts (``ssm_bench/scripts``, files without ``.py``) as a module.
"""
import importlib.machinery
import importlib.util
import os
import types

import rospy
import tf2_ros

from repo import REPO

REAL_BUFFER = tf2_ros.Buffer


def bench_script(name):
    path = os.path.join(REPO, "experiments", "safety_ssm", "ssm_bench", "scripts", name)
    loader = importlib.machinery.SourceFileLoader(name, path)
    module = importlib.util.module_from_spec(importlib.util.spec_from_loader(name, loader))
    loader.exec_module(module)
    return module


class Ros:
    """What the node under test advertised, subscribed and published."""

    def __init__(self, params):
        self.params = dict(params)
        self.publishers, self.subscribers, self.services, self.timers = {}, {}, {}, []

    def get_param(self, name, default=None):
        key = name.lstrip("~/")
        return self.params.get(key, default)

    def has_param(self, name):
        return name.lstrip("~/") in self.params


class FakePublisher:
    """Keeps every message; ``impl.latch`` as rospy's latched publisher keeps the last."""

    def __init__(self, ros, name, _cls=None, queue_size=None, latch=False, **_kw):
        self.name, self.sent = name, []
        self.impl = types.SimpleNamespace(latch=None)
        self._latch = latch
        ros.publishers[name] = self

    def publish(self, msg):
        self.sent.append(msg)
        if self._latch:
            self.impl.latch = msg

    def get_num_connections(self):
        return 1

    def unregister(self):
        pass


class FakeSubscriber:
    """Keeps its callback (and its argument): ``deliver(msg)`` calls it."""

    def __init__(self, ros, name, _cls=None, callback=None, callback_args=None, **_kw):
        self.name, self.callback, self.args = name, callback, callback_args
        ros.subscribers.setdefault(name, []).append(self)

    def deliver(self, msg):
        if self.args is None:
            self.callback(msg)
        else:
            self.callback(msg, self.args)

    def get_num_connections(self):
        return 1

    def unregister(self):
        pass


class FakeTimer:
    """A timer that never fires by itself."""

    def __init__(self, ros, period, callback, *_args, **_kw):
        self.period, self.callback, self.shut = period, callback, False
        ros.timers.append(self)

    def shutdown(self):
        self.shut = True


def install(monkeypatch, params=None):
    ros = Ros({"use_sim_time": True, **(params or {})})
    monkeypatch.setattr(rospy.rostime, "_rostime_initialized", True)    # simulated time, at 0
    monkeypatch.setattr(rospy.rostime, "_rostime_current", rospy.Time(0))
    monkeypatch.setattr(rospy, "get_param", ros.get_param)
    monkeypatch.setattr(rospy, "has_param", ros.has_param)
    monkeypatch.setattr(rospy, "Publisher", lambda *a, **k: FakePublisher(ros, *a, **k))
    monkeypatch.setattr(rospy, "Subscriber", lambda *a, **k: FakeSubscriber(ros, *a, **k))
    monkeypatch.setattr(rospy, "Timer", lambda *a, **k: FakeTimer(ros, *a, **k))
    monkeypatch.setattr(rospy, "Service",
                        lambda name, _cls, handler, **_k: ros.services.__setitem__(name, handler))
    monkeypatch.setattr(rospy, "wait_for_service", lambda *_a, **_k: None)
    monkeypatch.setattr(rospy, "ServiceProxy", lambda *_a, **_k: None)
    monkeypatch.setattr(rospy, "get_name", lambda: "/node_under_test")
    monkeypatch.setattr(tf2_ros, "Buffer",
                        lambda *a, **k: REAL_BUFFER(*a, **{**k, "debug": False}))
    return ros
