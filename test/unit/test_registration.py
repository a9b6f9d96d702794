"""BulkRegistration: rospy's registrations leave the creating thread and reach the master in
order, in multicall batches, with subscribers' answers handed back to rospy (no master: a fake
registrar and a fake XML-RPC master)."""
import errno
import os
import subprocess
import tempfile
import threading
import time
import types
from xmlrpc.server import SimpleXMLRPCServer

import pytest

from rospy.impl.registration import Registration, get_topic_manager
from rospy.impl.statistics import SubscriberStatisticsLogger

from epuck_vrep_compat.ros.transport import registration, withdraw
from epuck_vrep_compat.ros.transport.registration import BulkRegistration, withdraw_all

TIMEOUT_S = 60.0


class FakeRegistrar:
    """The parts of rospy's RegManager that BulkRegistration uses."""

    uri = "http://node:1234/"
    master_uri = "http://master:11311/"

    def __init__(self):
        self.synchronous = []          # registrations rospy itself made
        self.updates = []              # (topic, publisher URIs) handed back

    def reg_added(self, name, type_or_uri, reg_type):
        self.synchronous.append(("add", name))

    def reg_removed(self, name, type_or_uri, reg_type):
        self.synchronous.append(("remove", name))

    def publisher_update(self, name, uris):
        self.updates.append((name, uris))


class FakeMaster:
    """Answers system.multicall like rosmaster; blocks while ``gate`` is clear; fails the
    first ``failures`` calls like an unreachable master."""

    def __init__(self, failures=0):
        self.gate = threading.Event()
        self.gate.set()
        self.batches = []
        self.failures = failures
        self.system = self

    def multicall(self, calls):
        self.gate.wait(TIMEOUT_S)
        if self.failures:
            self.failures -= 1
            raise ConnectionRefusedError("master not there")
        self.batches.append([(c["methodName"], *c["params"]) for c in calls])
        return [[[1, "ok", ["http://pub:1/"] if c["methodName"] == "registerSubscriber" else 1]]
                for c in calls]


def register(registrar, count, reg_type=Registration.PUB):
    for i in range(count):
        registrar.reg_added(f"/t{i}", "std_msgs/Empty", reg_type)


def test_creating_does_not_wait_for_the_master_and_order_is_kept():
    registrar, master = FakeRegistrar(), FakeMaster()
    master.gate.clear()                               # the master does not answer yet
    bulk = BulkRegistration(registrar, batch_size=4, master=master)
    with bulk:
        register(registrar, 10)
        registrar.reg_removed("/t3", "std_msgs/Empty", Registration.PUB)
    assert bulk.sent == 0 and registrar.synchronous == []
    master.gate.set()
    assert bulk.wait(TIMEOUT_S)
    sent = [call for batch in master.batches for call in batch]
    # batches of at most 4; how the 11 calls split depends on when the thread woke
    assert all(1 <= len(b) <= 4 for b in master.batches) and len(master.batches) >= 3
    assert [c[0] for c in sent] == ["registerPublisher"] * 10 + ["unregisterPublisher"]
    assert [c[2] for c in sent] == [f"/t{i}" for i in range(10)] + ["/t3"]
    assert sent[0][3:] == ("std_msgs/Empty", FakeRegistrar.uri)
    assert sent[-1][3:] == (FakeRegistrar.uri,)
    assert bulk.sent == 11


def test_rospy_registers_itself_again_once_the_queue_is_empty():
    registrar, master = FakeRegistrar(), FakeMaster()
    bulk = BulkRegistration(registrar, master=master)
    with bulk:
        register(registrar, 2)
    assert bulk.wait(TIMEOUT_S)
    registrar.reg_added("/later", "std_msgs/Empty", Registration.PUB)
    assert registrar.synchronous == [("add", "/later")]
    assert sum(len(b) for b in master.batches) == 2


def test_a_registration_after_the_context_waits_for_the_queue_then_is_synchronous():
    registrar, master = FakeRegistrar(), FakeMaster()
    master.gate.clear()
    bulk = BulkRegistration(registrar, batch_size=2, master=master)
    with bulk:
        register(registrar, 3)
    done = threading.Event()

    def late():                                  # a service creating a topic at run time
        registrar.reg_added("/late", "std_msgs/Empty", Registration.PUB)
        done.set()
    threading.Thread(target=late, daemon=True).start()
    assert not done.wait(0.2)                    # the queue is not sent yet: it waits
    master.gate.set()
    assert done.wait(TIMEOUT_S)
    assert registrar.synchronous == [("add", "/late")]
    assert sum(len(b) for b in master.batches) == 3
    assert bulk.wait(TIMEOUT_S)


def test_subscribers_get_their_publishers_and_services_their_uri():
    registrar, master = FakeRegistrar(), FakeMaster()
    bulk = BulkRegistration(registrar, master=master)
    with bulk:
        registrar.reg_added("/cmd", "geometry_msgs/Twist", Registration.SUB)
        registrar.reg_added("/srv", "rosrpc://node:5/", Registration.SRV)
        registrar.reg_removed("/srv", "rosrpc://node:5/", Registration.SRV)
    assert bulk.wait(TIMEOUT_S)
    assert registrar.updates == [("/cmd", ["http://pub:1/"])]
    sent = [call for batch in master.batches for call in batch]   # however the thread split it
    assert sent[1][2:] == ("/srv", "rosrpc://node:5/", FakeRegistrar.uri)
    assert sent[2][0] == "unregisterService" and sent[2][2:] == ("/srv", "rosrpc://node:5/")


def test_an_unreachable_master_is_retried():
    registrar, master = FakeRegistrar(), FakeMaster(failures=2)
    bulk = BulkRegistration(registrar, master=master)
    with bulk:
        register(registrar, 3)
    assert bulk.wait(TIMEOUT_S)
    assert master.failures == 0
    assert [c[2] for c in master.batches[0]] == ["/t0", "/t1", "/t2"]


def test_rospys_per_topic_checks_pause_while_topics_are_created_and_come_back():
    original = SubscriberStatisticsLogger.__dict__["is_enabled"]
    topics = get_topic_manager()
    with BulkRegistration(FakeRegistrar(), master=FakeMaster()):
        assert SubscriberStatisticsLogger.__dict__["is_enabled"] is not original
        assert SubscriberStatisticsLogger.is_enabled() is False
        assert "check_all" in vars(topics)
    assert SubscriberStatisticsLogger.__dict__["is_enabled"] is original
    assert "check_all" not in vars(topics)


class FakeTopics:
    """The parts of rospy's topic and service managers that unregister_all reads."""

    def __init__(self, pubs=(), subs=(), services=()):
        self.pubs, self.subs, self.services = list(pubs), list(subs), list(services)

    def get_publications(self):
        return [(name, "std_msgs/Empty") for name in self.pubs]

    def get_subscriptions(self):
        return [(name, "std_msgs/Empty") for name in self.subs]

    def get_services(self):
        return [(name, f"rosrpc://node:1/{name}") for name in self.services]


class FakeListeners:
    def __init__(self):
        self.cleared = False

    def clear(self):
        self.cleared = True


def test_stopping_hands_every_withdrawal_over_in_order_and_rospy_unregisters_nothing(
        monkeypatch):
    topics = FakeTopics([f"/p{i}" for i in range(5)], ["/s0", "/s1"], ["/srv"])
    listeners = FakeListeners()
    handed = []
    monkeypatch.setattr(registration, "get_topic_manager", lambda: topics)
    monkeypatch.setattr(registration, "get_service_manager", lambda: topics)
    monkeypatch.setattr(registration, "get_registration_listeners", lambda: listeners)
    monkeypatch.setattr(withdraw, "hand_off", lambda uri, calls: handed.append((uri, calls)))
    cache = types.SimpleNamespace(d={"rosout_disable_topics_generation": False,
                                     "ns": {"a": 1, "empty": {}}})
    monkeypatch.setattr(registration, "get_param_server_cache", lambda: cache)
    assert withdraw_all(FakeRegistrar()) == 11
    [(uri, calls)] = handed
    assert uri == FakeRegistrar.master_uri
    assert [c[0] for c in calls] == ["unregisterPublisher"] * 5 + ["unregisterSubscriber"] * 2 \
        + ["unregisterService"] + ["unsubscribeParam"] * 3
    assert [c[1][1] for c in calls[:8]] == [f"/p{i}" for i in range(5)] + ["/s0", "/s1", "/srv"]
    assert calls[0][1][2:] == (FakeRegistrar.uri,)
    assert calls[7][1][2:] == ("rosrpc://node:1//srv",)
    assert [c[1][1:] for c in calls[8:]] == [
        (FakeRegistrar.uri, "/rosout_disable_topics_generation"), (FakeRegistrar.uri, "/ns/a"),
        (FakeRegistrar.uri, "/ns/empty")]
    assert listeners.cleared                  # closing a topic now calls no master


def test_the_withdrawing_process_sends_in_batches_and_ends_when_the_master_is_gone():
    calls = [("unregisterPublisher", ("/vrep", f"/t{i}", "http://node:1/")) for i in range(5)]
    master = FakeMaster()
    assert withdraw.send(master, calls, batch_size=2) == 5
    assert [len(b) for b in master.batches] == [2, 2, 1]
    assert [c[2] for b in master.batches for c in b] == [f"/t{i}" for i in range(5)]
    assert withdraw.send(FakeMaster(failures=1), calls, batch_size=2) == 0


def test_a_handed_over_withdrawal_reaches_a_master_from_a_process_of_its_own(tmp_path):
    """The real hand-over: a process started from the file the node wrote, against a small
    XML-RPC master in this test that records the multicalls it answers."""
    server = SimpleXMLRPCServer(("127.0.0.1", 0), logRequests=False, allow_none=True)
    server.register_multicall_functions()
    got = []
    server.register_function(lambda *args: (got.append(args), [1, "ok", 1])[1],
                             "unregisterPublisher")
    threading.Thread(target=server.serve_forever, daemon=True).start()
    try:
        uri = f"http://127.0.0.1:{server.server_address[1]}/"
        calls = [("unregisterPublisher", ["/vrep", f"/t{i}", "http://node:1/"]) for i in range(3)]
        pid = withdraw.hand_off(uri, calls)
        assert os.getsid(pid) == pid           # its own session: the node's group signals miss it
        deadline = time.monotonic() + TIMEOUT_S
        while len(got) < 3 and time.monotonic() < deadline:
            time.sleep(0.01)
        assert [a[1] for a in got] == ["/t0", "/t1", "/t2"]
    finally:
        server.shutdown()


def test_a_hand_over_that_cannot_start_its_process_leaves_no_file(tmp_path, monkeypatch):
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))

    def no_process(*_args, **_kwargs):
        raise OSError(errno.EMFILE, "Too many open files")
    monkeypatch.setattr(subprocess, "Popen", no_process)
    with pytest.raises(OSError):
        withdraw.hand_off("http://127.0.0.1:1/", [("unregisterPublisher", ["/vrep", "/t", "u"])])
    assert os.listdir(tmp_path) == []


def test_closing_drops_what_was_not_sent_and_nothing_is_queued_after():
    registrar, master = FakeRegistrar(), FakeMaster()
    master.gate.clear()                       # a first batch may be on its way, unanswered
    bulk = BulkRegistration(registrar, batch_size=2, master=master)
    with bulk:
        register(registrar, 6)
        closing = threading.Thread(target=bulk.close)
        closing.start()                       # drops the queue, waits for the batch on its way
        master.gate.set()
        closing.join(TIMEOUT_S)
        register(registrar, 2)                # after close: neither queued nor sent by rospy
    sent = [call[2] for batch in master.batches for call in batch]
    # at most the one batch that was on its way, the first registrations
    assert len(sent) <= 2 and sent == [f"/t{i}" for i in range(len(sent))]
    assert registrar.synchronous == []
