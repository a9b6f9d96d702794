"""bag_to_csv's safety plot (no master): a small bag of ssm_supervisor's topics becomes
ssm_<robot>.png, and a bag without them gets none."""
import os

import rosbag
import rospy
from std_msgs.msg import Float64

from epuck_vrep_compat.thesis import bag_export
from epuck_vrep_compat.thesis.ssm_plots import supervised_robots

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def test_a_safety_run_is_plotted_per_robot(tmp_path):
    path = str(tmp_path / "safety.bag")
    with rosbag.Bag(path, "w") as bag:
        for k in range(40):
            t = rospy.Time(5, 0) + rospy.Duration(0.05 * k)
            d = 2.0 - 0.04 * k
            bag.write("/ssm_supervisor/IRB140/separation", Float64(d), t)
            bag.write("/ssm_supervisor/IRB140/protective_separation", Float64(1.0), t)
            bag.write("/ssm_supervisor/IRB140/scale", Float64(max(0.0, min(1.0, d - 1.0))), t)
    outdir = str(tmp_path / "out")
    bag_export.export(path, outdir)
    png = os.path.join(outdir, "ssm_IRB140.png")
    with open(png, "rb") as f:
        assert f.read(8) == PNG_SIGNATURE
    assert supervised_robots(["/ssm_supervisor/SIX/separation", "/ssm_supervisor/SIX/scale",
                              "/other/separation"]) == ["SIX"]
