#!/usr/bin/python3
"""A client process for the fault tests (run by test_faults.py, never by rostest itself).

--mode client [--set-led]: drives /ePuck0 with cmd_vel at 10 Hz, optionally sets its LEDs once,
  and prints "LATCHED <values>" when the latched /ePuck0/led_state arrives.
--mode reader: subscribes to /tf and the camera and prints "CONNECTED" once both publishers
  know it; the test then stops it with SIGSTOP, so it never reads again.
"""
import argparse
import sys
import time

import rospy
from geometry_msgs.msg import Twist
from sensor_msgs.msg import Image
from std_msgs.msg import UInt8MultiArray
from tf2_msgs.msg import TFMessage

PATTERN = [1, 0, 1, 0, 1, 0, 1, 0, 1]


def client(set_led):
    rospy.init_node("fault_client")
    rospy.Subscriber("/ePuck0/led_state", UInt8MultiArray,
                     lambda m: print("LATCHED", list(bytearray(m.data)), flush=True))
    cmd = rospy.Publisher("/ePuck0/cmd_vel", Twist, queue_size=10)
    if set_led:
        led = rospy.Publisher("/ePuck0/cmd_led", UInt8MultiArray, queue_size=1, latch=True)
        led.publish(UInt8MultiArray(data=bytes(PATTERN)))
    twist = Twist()
    twist.angular.z = 0.5
    while not rospy.is_shutdown():
        cmd.publish(twist)
        time.sleep(0.1)


def reader():
    rospy.init_node("stuck_reader", anonymous=True)
    rospy.Subscriber("/tf", TFMessage, lambda m: None, queue_size=1)
    rospy.Subscriber("/ePuck0/camera", Image, lambda m: None, queue_size=1)
    print("CONNECTED", flush=True)
    rospy.spin()


if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("--mode", choices=("client", "reader"), required=True)
    ap.add_argument("--set-led", action="store_true")
    args = ap.parse_args(rospy.myargv()[1:])
    client(args.set_led) if args.mode == "client" else reader()
    sys.exit(0)
