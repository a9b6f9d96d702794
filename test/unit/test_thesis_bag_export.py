"""bag_to_csv (no master): CSV files identical to ``rostopic echo -p -b`` on a small bag
written here with rosbag's API, the thesis's plots as PNG files, clean failures on bad bags."""
import os
import subprocess

import numpy as np
import pytest
import rosbag
import rospy
from sensor_msgs.msg import Image
from std_msgs.msg import Float32, Header, String

from epuck_vrep_compat.msg import (
    JointHandles, headerGiunto, posOrAssGiunto, posOrRelGiunto, proxData, vett_JointHandles,
    vett_posOrAssGiunto, vett_posOrRelGiunto, vett_proxData)
from epuck_vrep_compat.thesis import bag_export
from epuck_vrep_compat.thesis.bag_plots import joint_tracks, match_by_time

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
STEPS = 20


def _joint(cls, k, indice, frame):
    head = headerGiunto(Header(seq=k, stamp=rospy.Time(10, 50_000_000 * k), frame_id=frame),
                        indice, 20 + indice, f"SIX_joint{indice + 1}")
    return cls(head, [0.5 + 0.01 * k, -2.2 + indice, 0.45], [1.5707, 1.3294 - 0.1 * k, 1.5708])


def write_bag(path):
    with rosbag.Bag(path, "w") as bag:
        for k in range(STEPS):
            t = rospy.Time(100, 0) + rospy.Duration(0.05 * k)
            bag.write("/Comau_PosOrAss", vett_posOrAssGiunto(
                [_joint(posOrAssGiunto, k, i, "world") for i in range(2)]), t)
            bag.write("/vrep/Blob_Camera_0_X", Float32(0.4 + 0.02 * k), t)
            bag.write("/vrep/Blob_Camera_0_Y", Float32(0.1 + 0.03 * k),
                      t + rospy.Duration(0.002))
        bag.write("/Comau_PosOrRel", vett_posOrRelGiunto(
            [_joint(posOrRelGiunto, 0, 0, "SIX")]), rospy.Time(100, 1))
        bag.write("/prox_data", vett_proxData([proxData(1, 77, "Proximity_sensor10", [0.1, 0, 0.05],
                                                        [0, 0, -1])]), rospy.Time(100, 2))
        bag.write("/note", String("a, b"), rospy.Time(100, 3))
        bag.write("/Camera_Image_0", Image(height=1, width=2, encoding="rgb8", step=6,
                                           data=bytes(range(6))), rospy.Time(100, 4))
        # the first message's arrays are empty: rostopic's header then has no field columns
        bag.write("/Comau_JointHandles", vett_JointHandles([]), rospy.Time(100, 5))
        bag.write("/Comau_JointHandles", vett_JointHandles([JointHandles(0, 21, "SIX_joint1")]),
                  rospy.Time(100, 6))


@pytest.fixture(scope="module")
def exported(tmp_path_factory):
    folder = tmp_path_factory.mktemp("bag")
    bag = str(folder / "run.bag")
    write_bag(bag)
    out = str(folder / "out")
    assert bag_export.main([bag, "-o", out]) == 0
    return bag, out


TOPICS = ["/Comau_PosOrAss", "/Comau_PosOrRel", "/vrep/Blob_Camera_0_X", "/prox_data", "/note",
          "/Camera_Image_0", "/Comau_JointHandles"]


@pytest.mark.parametrize("topic", TOPICS)
def test_csv_is_what_rostopic_echo_p_b_prints(exported, topic):
    bag, out = exported
    expected = subprocess.run(["rostopic", "echo", "-p", "-b", bag, topic], check=True,
                              capture_output=True, text=True, timeout=60).stdout
    with open(os.path.join(out, bag_export.csv_name(topic)), encoding="utf-8") as f:
        assert f.read() == expected


def test_nested_arrays_of_messages_are_numbered_then_nested(exported):
    _, out = exported
    with open(os.path.join(out, "Comau_PosOrAss.csv"), encoding="utf-8") as f:
        header, first = f.readline().rstrip("\n").split(","), f.readline().split(",")
    assert header[:3] == ["%time", "field.posizioneOrientamento0.headerGiunto.header.seq",
                          "field.posizioneOrientamento0.headerGiunto.header.stamp"]
    assert "field.posizioneOrientamento1.Posizione_Assoluta2" in header
    assert "field.posizioneOrientamento1.headerGiunto.nome" in header
    assert first[0] == str(rospy.Time(100, 0).to_nsec()) and len(first) == len(header)


def test_plots_are_png_files_and_missing_topics_are_skipped(exported, capsys):
    _, out = exported
    for name in ["blob_camera_0.png", "Comau_joint_1.png", "Comau_joint_2.png"]:
        with open(os.path.join(out, name), "rb") as f:
            data = f.read()
        assert data.startswith(PNG_SIGNATURE) and len(data) > 5000
    assert not os.path.exists(os.path.join(out, "blob_camera_1.png"))
    assert not any(n.startswith(("Irb_", "YouBot_")) and n.endswith(".png")
                   for n in os.listdir(out))


def test_report_names_what_was_skipped(tmp_path, capsys):
    bag = str(tmp_path / "run.bag")
    write_bag(bag)
    assert bag_export.main([bag]) == 0
    report = capsys.readouterr().out
    assert "skipped blob_camera_1.png: no /vrep/Blob_Camera_1_X, /vrep/Blob_Camera_1_Y" in report
    assert "skipped Irb_joint_*.png: no /Irb_PosOrAss in the bag" in report
    assert os.path.isfile(str(tmp_path / "run_export" / "Comau_PosOrAss.csv"))


def test_blob_samples_pair_by_nearest_time():
    x, y = match_by_time([0.0, 0.05, 0.10, 0.50], [1, 2, 3, 4], [0.051, 0.002, 0.099],
                         [20, 10, 30])
    assert list(x) == [1, 2, 3] and list(y) == [10, 20, 30]     # 0.50 has no partner
    x, y = match_by_time([0.0], [1], [], [])
    assert len(x) == 0 and len(y) == 0


def test_joint_tracks_use_the_stamp_or_else_the_receive_time():
    msgs = [(vett_posOrAssGiunto([_joint(posOrAssGiunto, k, 0, "world")]), rospy.Time(100 + k))
            for k in range(3)]
    msgs[2][0].posizioneOrientamento[0].headerGiunto.header.stamp = rospy.Time(0)
    (nome, t, xyz), = joint_tracks(msgs).values()
    assert nome == "SIX_joint1"
    np.testing.assert_allclose(t[:2], [0.0, 0.05])
    assert t[2] == pytest.approx(102 - 10.0)
    np.testing.assert_allclose(xyz[1], [0.51, -2.2, 0.45], rtol=1e-6)


def test_missing_corrupt_and_truncated_bags_exit_non_zero(tmp_path, capsys):
    assert bag_export.main([str(tmp_path / "nope.bag")]) == 1
    assert "no such bag file" in capsys.readouterr().err
    garbage = tmp_path / "garbage.bag"
    garbage.write_bytes(b"this is not a bag\n" * 100)
    assert bag_export.main([str(garbage)]) == 1
    assert "cannot read" in capsys.readouterr().err
    good = tmp_path / "good.bag"
    write_bag(str(good))
    truncated = tmp_path / "truncated.bag"
    truncated.write_bytes(good.read_bytes()[:3000])
    assert bag_export.main([str(truncated)]) == 1
    assert "cannot read" in capsys.readouterr().err


def test_the_command_runs_with_rosrun(tmp_path):
    bag = str(tmp_path / "run.bag")
    write_bag(bag)
    ok = subprocess.run(["rosrun", "epuck_vrep_compat", "bag_to_csv", bag, "-o",
                         str(tmp_path / "o")], capture_output=True, text=True, timeout=120)
    assert ok.returncode == 0, ok.stderr
    assert os.path.isfile(str(tmp_path / "o" / "prox_data.csv"))
    bad = subprocess.run(["rosrun", "epuck_vrep_compat", "bag_to_csv", str(tmp_path / "x.bag")],
                         capture_output=True, text=True, timeout=60)
    assert bad.returncode == 1 and "bag_to_csv: cannot read" in bad.stderr
