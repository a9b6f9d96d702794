"""The supervisor's separation query keeps one connection and opens it anew when it breaks."""
import types

import rospy

import fake_ros
from epuck_vrep_compat.nodes.ssm_supervisor import SsmSupervisor


class Proxy:
    """A persistent proxy whose calls follow a script: an exception raised, or an answer."""

    made = []

    def __init__(self, script, **kwargs):
        self.script, self.kwargs, self.closed = script, kwargs, False
        Proxy.made.append(self)

    def __call__(self, _request):
        outcome = self.script.pop(0)
        if isinstance(outcome, Exception):
            raise outcome
        return outcome

    def close(self):
        self.closed = True


def supervisor(monkeypatch, script):
    fake_ros.install(monkeypatch, {"robots": ["IRB140"], "lockstep": True})
    Proxy.made = []
    monkeypatch.setattr(rospy, "ServiceProxy", lambda *_a, **kw: Proxy(script, **kw))
    return SsmSupervisor()


def answer(success=True, message=""):
    return types.SimpleNamespace(success=success, message=message)


def test_one_persistent_connection_serves_every_query(monkeypatch):
    ok = answer()
    sup = supervisor(monkeypatch, [ok, ok, ok])
    assert [sup.separation(object()) for _ in range(3)] == [(ok, None)] * 3
    assert len(Proxy.made) == 1 and Proxy.made[0].kwargs == {"persistent": True}


def test_a_broken_connection_is_opened_again_and_the_query_asked_once_more(monkeypatch):
    ok = answer()
    sup = supervisor(monkeypatch, [rospy.ServiceException("transport error"), ok])
    assert sup.separation(object()) == (ok, None)
    assert len(Proxy.made) == 2 and Proxy.made[0].closed and not Proxy.made[1].closed


def test_a_query_failing_twice_is_a_failure_that_says_why(monkeypatch):
    sup = supervisor(monkeypatch, [rospy.ServiceException("gone"), OSError("refused")])
    result, why = sup.separation(object())
    assert result is None and why == "separation query failed: refused"
    sup.query.script.append(answer(False, "no operator"))
    assert sup.separation(object()) == (None, "no operator")
