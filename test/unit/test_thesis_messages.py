"""The thesis's messages (chapter 4): field names, types and order as the thesis, checked
through the generated classes and their MD5 sums (computed here from the field lists, the way
genmsg does, so a changed field, type or order fails)."""
import hashlib
import io

import pytest
from std_msgs.msg import Header

from epuck_vrep_compat import msg as m

FIELDS = {
    "ComauMsg": [("int32", "hComauRobot"), ("int32[7]", "hComauJoint")],
    "IrbMsg": [("int32", "hIrbRobot"), ("int32[6]", "hIrbJoint")],
    "YouBotMsg": [("int32", "hYouBotRobot"), ("int32[16]", "hYouBotJoint")],
    "JointHandles": [("int32", "indice"), ("int32", "handle"), ("string", "nome")],
    "vett_JointHandles": [("JointHandles[]", "handles")],
    "headerGiunto": [("std_msgs/Header", "header"), ("int32", "indice"), ("int32", "handle"),
                     ("string", "nome")],
    "posOrAssGiunto": [("headerGiunto", "headerGiunto"), ("float32[3]", "Posizione_Assoluta"),
                       ("float32[3]", "Orientamento_Assoluto")],
    "posOrRelGiunto": [("headerGiunto", "headerGiunto"), ("float32[3]", "Posizione_Relativa"),
                       ("float32[3]", "Orientamento_Relativo")],
    "vett_posOrAssGiunto": [("posOrAssGiunto[]", "posizioneOrientamento")],
    "vett_posOrRelGiunto": [("posOrRelGiunto[]", "posizioneOrientamento")],
    "proxData": [("int32", "state"), ("int32", "objectHandle"), ("string", "nomeProx"),
                 ("float32[3]", "point"), ("float32[3]", "normal")],
    "vett_proxData": [("proxData[]", "proxData")],
}
PRIMITIVES = {"int32", "float32", "string"}


def expected_md5(name):
    """ROS's MD5 rule: the definition's lines, nested types replaced by their own MD5."""
    lines = []
    for field_type, field_name in FIELDS[name]:
        base = field_type.split("[")[0]
        if base in PRIMITIVES:
            lines.append(f"{field_type} {field_name}")
        else:
            md5 = Header._md5sum if base == "std_msgs/Header" else expected_md5(base)
            lines.append(f"{md5} {field_name}")
    return hashlib.md5("\n".join(lines).encode()).hexdigest()


@pytest.mark.parametrize("name", sorted(FIELDS))
def test_fields_in_the_theses_order(name):
    cls = getattr(m, name)
    assert cls._type == f"epuck_vrep_compat/{name}"
    assert list(cls.__slots__) == [field for _, field in FIELDS[name]]
    types = [t.replace("epuck_vrep_compat/", "") for t in cls._slot_types]
    assert types == [t for t, _ in FIELDS[name]]


@pytest.mark.parametrize("name", sorted(FIELDS))
def test_md5_follows_from_the_field_list(name):
    assert getattr(m, name)._md5sum == expected_md5(name)


def test_a_nested_message_round_trips():
    joint = m.posOrAssGiunto(m.headerGiunto(Header(seq=3, frame_id="world"), 1, 42, "SIX_joint2"),
                             [0.5362, -2.2258, 0.45], [1.5707, 1.3294, 1.5708])
    sent = m.vett_posOrAssGiunto(posizioneOrientamento=[joint, joint])
    buff = io.BytesIO()
    sent.serialize(buff)
    got = m.vett_posOrAssGiunto().deserialize(buff.getvalue())
    assert len(got.posizioneOrientamento) == 2
    head = got.posizioneOrientamento[1].headerGiunto
    assert (head.indice, head.handle, head.nome, head.header.frame_id) == (1, 42, "SIX_joint2",
                                                                           "world")
    assert got.posizioneOrientamento[0].Posizione_Assoluta == pytest.approx(
        [0.5362, -2.2258, 0.45], abs=1e-6)
