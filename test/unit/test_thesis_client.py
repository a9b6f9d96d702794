"""What the thesis's nodes share (no master): parameter validation, throttled warnings, the
/vrep client's failure handling and handle cache, with rospy's calls replaced by fakes."""
import pytest
import rospy
from vrep_common.srv import simRosGetObjectGroupDataResponse, simRosGetObjectHandleResponse

from epuck_vrep_compat.compat.thesis_names import COMAU, PROX_SENSOR_NAMES, YOUBOT
from epuck_vrep_compat.thesis import params, vrep_client


@pytest.fixture
def set_params(monkeypatch):
    values = {}
    monkeypatch.setattr(rospy, "get_param", lambda key, default=None: values.get(key, default))
    return values


@pytest.fixture
def warnings(monkeypatch):
    lines = []
    monkeypatch.setattr(rospy, "logwarn", lambda fmt, *args: lines.append(fmt % args))
    return lines


def test_defaults_are_the_cells_names(set_params):
    assert params.read_rate_hz() == 20.0
    assert params.read_names("comau_joints", COMAU.joint_names)[6] == "SIX_joint7"
    assert len(YOUBOT.joint_names) == 16 and YOUBOT.joint_names[-1] == "youBotGripperPinionJoint"
    assert PROX_SENSOR_NAMES == tuple(f"Proximity_sensor{i}" for i in range(10, 21))


@pytest.mark.parametrize("key, value, reader", [
    ("~rate", 0.0, lambda: params.read_rate_hz()),
    ("~rate", "fast", lambda: params.read_rate_hz()),
    ("~rate", float("nan"), lambda: params.read_rate_hz()),
    ("~comau_robot", "", lambda: params.read_name("comau_robot", "SIX")),
    ("~comau_joints", ["a", "b"], lambda: params.read_names("comau_joints", COMAU.joint_names)),
    ("~sensor_names", [], lambda: params.read_names("sensor_names", PROX_SENSOR_NAMES, False)),
    ("~sensor_names", ["ok", 3], lambda: params.read_names("sensor_names", PROX_SENSOR_NAMES,
                                                           False)),
    ("~far_clipping_m", 0.2, lambda: params.read_float("far_clipping_m", 5.0, minimum=0.5)),
])
def test_unusable_parameters_name_themselves(set_params, key, value, reader):
    set_params[key] = value
    with pytest.raises(params.ParamError, match=key.lstrip("~")):
        reader()


def test_throttled_log_says_each_kind_once_per_period(warnings):
    log = vrep_client.ThrottledLog(period_s=60.0)
    for _ in range(5):
        log.warn("a", "first %d", 1)
        log.warn("b", "second")
    assert warnings == ["first 1", "second"]


class FakeProxy:
    """A persistent proxy whose answers come from a script shared by all instances."""
    answers = []
    created = 0

    def __init__(self, name, srv_class, persistent=False):
        assert persistent
        FakeProxy.created += 1
        self.closed = False

    def __call__(self, **request):
        answer = FakeProxy.answers.pop(0)
        if isinstance(answer, Exception):
            raise answer
        return answer

    def close(self):
        self.closed = True


@pytest.fixture
def client(monkeypatch, warnings):
    FakeProxy.answers, FakeProxy.created = [], 0
    monkeypatch.setattr(rospy, "ServiceProxy", FakeProxy)
    return vrep_client.VrepClient({"simRosGetObjectHandle": object,
                                   "simRosGetObjectGroupData": object})


def test_a_broken_connection_is_warned_and_reopened(client, warnings):
    FakeProxy.answers = [rospy.ServiceException("transport error"),
                         simRosGetObjectHandleResponse(handle=7)]
    assert client.call("simRosGetObjectHandle", objectName="x") is None
    assert len(warnings) == 1 and "/vrep/simRosGetObjectHandle failed" in warnings[0]
    assert client.call("simRosGetObjectHandle", objectName="x").handle == 7
    assert FakeProxy.created == 2


def test_handles_are_remembered_once_found_and_missing_ones_warned(client, warnings):
    FakeProxy.answers = [simRosGetObjectHandleResponse(handle=-1),
                         simRosGetObjectHandleResponse(handle=5)]
    assert client.handle("camera0", "vision sensor") == -1
    assert "no vision sensor named 'camera0'" in warnings[0]
    assert client.handle("camera0") == 5
    assert client.handle("camera0") == 5            # no third call: the script is empty
    client.forget_handle("camera0")                 # e.g. the sensor stopped answering
    FakeProxy.answers = [simRosGetObjectHandleResponse(handle=8)]
    assert client.handle("camera0") == 8


def test_object_names_map_handles_to_names(client):
    FakeProxy.answers = [simRosGetObjectGroupDataResponse(handles=[3, 9], strings=["a", "b"])]
    assert client.object_names() == {3: "a", 9: "b"}
    FakeProxy.answers = [rospy.ServiceException("down")]
    assert client.object_names() is None
