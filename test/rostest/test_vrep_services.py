#!/usr/bin/python3
"""The /vrep simRos* services answer as V-REP 3.3.0's plugin did, on the fixture world
test/worlds/vrep_services.yaml (ePuck faces a wall 0.163 m ahead of its camera)."""
import math
import threading
import time

import rosgraph.masterapi
import rostest
import vrep_common.srv
from vrep_common.msg import VrepInfo

from epuck_vrep_compat.compat import vrep_codes as vc

from sim_test_helpers import PKG, Collector, SimTestCase, call, handle, wait_sim_time

WALL_AHEAD_OF_CAMERA_M = 0.5 - (0.3 + 0.037)
NEAR_M, FAR_M = 0.005, 2.0                  # CameraSpec defaults
CAMERA_W, CAMERA_H = 32, 24                 # vrep_services.test
HANDLE_ALL, HANDLE_PARENT, WORLD = -2, -11, -1
NOT_ADVERTISED = {"simRosAppendStringSignal"}


def info_seq(msg):
    seq = msg.headerInfo.seq
    return seq - (1 << 32) if seq >= 1 << 31 else seq


class VrepServices(SimTestCase):
    NODE = "test_vrep_services"
    SERVICES = ("/vrep/simRosGetInfo",)
    SERVICE_TIMEOUT_S = 30.0

    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        cls.info = Collector("/vrep/info", VrepInfo)
        cls.info.wait(1, timeout_s=30)

    def setUp(self):
        call("simRosSynchronous", enable=0)
        call("simRosStartSimulation")
        call("simRosGetLastErrors")

    def last_errors(self):
        res = call("simRosGetLastErrors")
        errors = res.errorStrings.split("\0")[:-1] if res.errorStrings else []
        self.assertEqual(res.errorCnt, len(errors))
        return errors

    def wait_info(self, predicate, timeout_s=10.0):
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            msg = self.info.latest()
            if msg is not None and predicate(msg):
                return msg
            time.sleep(0.01)
        self.fail(f"/vrep/info never satisfied the condition; last: {self.info.latest()}")

    def drive(self, robot_suffix, rad_s):
        for side in ("left", "right"):
            res = call("simRosSetJointTargetVelocity",
                       handle=handle(f"ePuck_{side}Joint{robot_suffix}"), targetVelocity=rad_s)
            self.assertEqual(res.result, 1)

    def set_base_pose(self, name, x, y, yaw):
        pose = vrep_common.srv.simRosSetObjectPoseRequest().pose
        pose.position.x, pose.position.y = x, y
        pose.orientation.z, pose.orientation.w = math.sin(yaw / 2), math.cos(yaw / 2)
        return call("simRosSetObjectPose", handle=handle(name), relativeToObjectHandle=WORLD,
                    pose=pose).result

    # --- handles, objects, group data --------------------------------------------------------
    def test_handles_by_name(self):
        left, sensor = handle("ePuck_leftJoint"), handle("ePuck_proxSensor0#0")
        self.assertGreater(left, 0)
        self.assertGreater(sensor, 0)
        self.assertNotEqual(left, handle("ePuck_leftJoint#0"))
        self.assertEqual(handle("ePuck_leftJoint#"), left)
        self.assertEqual(call("simRosGetObjectParent", handle=sensor).parentHandle,
                         handle("ePuck#0"))
        self.assertEqual(handle("no_such_object"), -1)
        self.assertEqual(handle(""), -1)

    def test_objects_by_type_parent_and_child(self):
        joints = call("simRosGetObjects", objectType=1)
        self.assertEqual(joints.result, 4)
        self.assertEqual(sorted(joints.handles),
                         sorted(handle(f"ePuck_{s}Joint{r}") for s in ("left", "right")
                                for r in ("", "#0")))
        self.assertEqual(call("simRosGetObjects", objectType=5).result, 16)
        everything = call("simRosGetObjects", objectType=HANDLE_ALL)
        self.assertEqual(everything.result, len(everything.handles))
        self.assertGreater(everything.result, 2 * 20)
        self.assertEqual(call("simRosGetObjects", objectType=500).result, 0)
        base = handle("ePuck")
        self.assertEqual(call("simRosGetObjectParent", handle=base).parentHandle, -1)
        child = call("simRosGetObjectChild", handle=base, index=0).childHandle
        self.assertEqual(call("simRosGetObjectParent", handle=child).parentHandle, base)
        self.assertEqual(call("simRosGetObjectChild", handle=base, index=999).childHandle, -1)

    def test_group_data(self):
        names = call("simRosGetObjectGroupData", objectType=109, dataType=0)
        self.assertEqual(len(names.handles), len(names.strings))
        self.assertIn("ePuck_camera", names.strings)
        self.assertIn("ePuck_camera#0", names.strings)
        types = call("simRosGetObjectGroupData", objectType=1, dataType=1)
        self.assertEqual(list(types.intData), [1, 1, 1, 1])
        parents = call("simRosGetObjectGroupData", objectType=1, dataType=2)
        self.assertEqual(list(parents.intData), [handle("ePuck")] * 2 + [handle("ePuck#0")] * 2)
        shapes = call("simRosGetObjectGroupData", objectType=0, dataType=3)
        k = list(shapes.handles).index(handle("ePuck#0"))
        pose = call("simRosGetObjectPose", handle=handle("ePuck#0"), relativeToObjectHandle=WORLD)
        p = pose.pose.pose.position
        for got, want in zip(shapes.floatData[3 * k:3 * k + 3], (p.x, p.y, p.z)):
            self.assertAlmostEqual(got, want, delta=0.01)
        joints = call("simRosGetObjectGroupData", objectType=1, dataType=15)
        self.assertEqual(len(joints.handles), 4)
        self.assertEqual(len(joints.floatData), 8)
        prox = call("simRosGetObjectGroupData", objectType=5, dataType=13)
        self.assertEqual((len(prox.handles), len(prox.intData), len(prox.floatData)),
                         (16, 32, 96))
        self.assertTrue(all(state in (0, 1) for state in prox.intData[0::2]))
        bad = call("simRosGetObjectGroupData", objectType=1, dataType=77)
        self.assertEqual((list(bad.handles), list(bad.floatData)), ([], []))

    # --- poses and joints -------------------------------------------------------------------
    def test_pose_round_trip_and_relative_poses(self):
        self.drive("#0", 0.0)
        self.assertEqual(self.set_base_pose("ePuck#0", -0.2, 0.3, 0.7), 1)
        res = call("simRosGetObjectPose", handle=handle("ePuck#0"), relativeToObjectHandle=WORLD)
        self.assertEqual(res.result, 1)
        p, q = res.pose.pose.position, res.pose.pose.orientation
        self.assertAlmostEqual(p.x, -0.2, places=4)
        self.assertAlmostEqual(p.y, 0.3, places=4)
        self.assertAlmostEqual(2 * math.atan2(q.z, q.w), 0.7, places=4)
        self.assertEqual(res.pose.header.frame_id, "")
        self.assertGreaterEqual(res.pose.header.seq, 0)
        joint = handle("ePuck_leftJoint#0")
        for relative_to in (HANDLE_PARENT, handle("ePuck#0")):
            rel = call("simRosGetObjectPose", handle=joint, relativeToObjectHandle=relative_to)
            p = rel.pose.pose.position
            self.assertEqual(rel.result, 1)
            self.assertAlmostEqual(p.x, 0.0, places=5)
            self.assertAlmostEqual(p.y, 0.0265, places=5)
            self.assertAlmostEqual(p.z, 0.02, places=5)
        point = vrep_common.srv.simRosSetObjectPositionRequest().position
        point.x, point.y = -0.1, 0.35
        self.assertEqual(call("simRosSetObjectPosition", handle=handle("ePuck#0"),
                              relativeToObjectHandle=WORLD, position=point).result, 1)
        res = call("simRosGetObjectPose", handle=handle("ePuck#0"), relativeToObjectHandle=WORLD)
        self.assertAlmostEqual(res.pose.pose.position.x, -0.1, places=4)
        self.assertAlmostEqual(2 * math.atan2(res.pose.pose.orientation.z,
                                              res.pose.pose.orientation.w), 0.7, places=4)
        self.assertEqual(call("simRosSetObjectPosition", handle=joint,
                              relativeToObjectHandle=WORLD, position=point).result, -1)

    def test_joint_target_velocity_turns_the_wheel_and_moves_the_robot(self):
        left = handle("ePuck_leftJoint#0")
        before = call("simRosGetJointState", handle=left)
        self.assertEqual(before.result, 1)
        self.assertEqual(list(before.state.name), ["ePuck_leftJoint#0"])
        start = call("simRosGetObjectPose", handle=handle("ePuck#0"), relativeToObjectHandle=WORLD)
        try:
            self.drive("#0", 5.0)
            wait_sim_time(1.0)
            during = call("simRosGetJointState", handle=left)
            self.assertAlmostEqual(during.state.velocity[0], 5.0, delta=1.25)  # 5 % slip per step
            self.assertNotAlmostEqual(during.state.position[0], before.state.position[0], places=2)
        finally:
            self.drive("#0", 0.0)
        end = call("simRosGetObjectPose", handle=handle("ePuck#0"), relativeToObjectHandle=WORLD)
        moved = math.hypot(end.pose.pose.position.x - start.pose.pose.position.x,
                           end.pose.pose.position.y - start.pose.pose.position.y)
        self.assertGreater(moved, 0.05)
        every = call("simRosGetJointState", handle=HANDLE_ALL)
        self.assertEqual(len(every.state.name), 4)
        self.assertEqual(len(every.state.effort), 4)
        right = handle("ePuck_rightJoint#0")
        ok = call("simRosSetJointState", handles=[left, right], setModes=[2, 2], values=[0, 0])
        self.assertEqual(ok.result, 2)
        mismatched = call("simRosSetJointState", handles=[left, right], setModes=[2],
                          values=[0, 0])
        self.assertEqual(mismatched.result, -1)
        self.assertEqual(call("simRosSetJointPosition", handle=left, position=1.0).result, -1)

    # --- sensors ------------------------------------------------------------------------------
    def test_vision_image_sizes_and_encodings(self):
        camera = handle("ePuck_camera")
        rgb = call("simRosGetVisionSensorImage", handle=camera, options=0)
        mono = call("simRosGetVisionSensorImage", handle=camera, options=1)
        for res, encoding, bpp in ((rgb, "rgb8", 3), (mono, "mono8", 1)):
            self.assertEqual(res.result, 1)
            image = res.image
            self.assertEqual((image.width, image.height), (CAMERA_W, CAMERA_H))
            self.assertEqual(image.encoding, encoding)
            self.assertEqual(image.step, CAMERA_W * bpp)
            self.assertEqual(image.is_bigendian, 0)
            self.assertEqual(len(image.data), CAMERA_W * CAMERA_H * bpp)
            self.assertEqual(image.header.frame_id, "")
        bad = call("simRosGetVisionSensorImage", handle=handle("ePuck_leftJoint"), options=0)
        self.assertEqual(bad.result, -1)
        self.assertEqual(call("simRosGetObjectIntParameter", handle=camera,
                              parameterID=1002).parameterValue, CAMERA_W)

    def test_depth_buffer_and_vision_statistics_at_the_wall(self):
        self.assertEqual(self.set_base_pose("ePuck", 0.3, 0.0, 0.0), 1)
        res = call("simRosGetVisionSensorDepthBuffer", handle=handle("ePuck_camera"))
        self.assertEqual(res.result, 1)
        self.assertEqual(list(res.resolution), [CAMERA_W, CAMERA_H])
        self.assertEqual(len(res.buffer), CAMERA_W * CAMERA_H)
        centre = res.buffer[(CAMERA_H // 2) * CAMERA_W + CAMERA_W // 2]
        expected = (WALL_AHEAD_OF_CAMERA_M - NEAR_M) / (FAR_M - NEAR_M)
        self.assertAlmostEqual(centre, expected, delta=0.003)
        # V-REP's row order: the first row is the bottom of the image (the floor, near), the
        # last the top (above the 5 cm wall: nothing, 1.0)
        self.assertLess(max(res.buffer[:CAMERA_W]), expected)
        self.assertEqual(min(res.buffer[-CAMERA_W:]), 1.0)
        read = call("simRosReadVisionSensor", handle=handle("ePuck_camera"))
        self.assertEqual(read.result, 0)
        self.assertEqual(list(read.packetSizes), [15])
        low, high, mean = read.packetData[0:5], read.packetData[5:10], read.packetData[10:15]
        self.assertTrue(all(0.0 <= a <= m <= b <= 1.0 for a, m, b in zip(low, mean, high)))
        self.assertEqual(high[4], 1.0)

    def test_proximity_sensor_and_missing_devices(self):
        res = call("simRosReadProximitySensor", handle=handle("ePuck_proxSensor0"))
        self.assertIn(res.result, (0, 1))
        self.assertEqual(len(res.detectedPoint), 3)
        self.assertEqual(len(res.normalVector), 3)
        self.assertEqual(call("simRosReadProximitySensor", handle=handle("ePuck")).result, -1)
        self.assertEqual(call("simRosReadForceSensor", handle=handle("ePuck")).result, -1)
        self.assertEqual(call("simRosReadCollision", handle=1).collisionState, -1)
        self.assertEqual(call("simRosReadDistance", handle=1).result, -1)

    # --- simulation ---------------------------------------------------------------------------
    def test_synchronous_mode_advances_one_frame_per_trigger(self):
        self.assertEqual(call("simRosSynchronousTrigger").result, -1)     # not synchronous
        try:
            self.assertEqual(call("simRosSynchronous", enable=1).result, 1)
            time.sleep(0.3)
            first = info_seq(self.info.latest())
            for k in range(1, 6):
                self.assertEqual(call("simRosSynchronousTrigger").result, 1)
                self.wait_info(lambda m, k=k: info_seq(m) == first + k)
                time.sleep(0.2)
                self.assertEqual(info_seq(self.info.latest()), first + k)
                self.assertEqual(call("simRosGetInfo").headerInfo.seq, first + k)
        finally:
            call("simRosSynchronous", enable=0)
        self.wait_info(lambda m: info_seq(m) > first + 10)

    def test_start_pause_stop_change_the_state_bits(self):
        self.wait_info(lambda m: m.simulatorState.data & 3 == 1)
        self.assertEqual(call("simRosPauseSimulation").result, 1)
        self.wait_info(lambda m: m.simulatorState.data & 3 == 3)
        self.assertEqual(call("simRosGetInfo").simulatorState & 3, 3)
        self.assertEqual(call("simRosStartSimulation").result, 1)
        self.wait_info(lambda m: m.simulatorState.data & 3 == 1)
        self.assertEqual(call("simRosStopSimulation").result, 1)
        stopped = self.wait_info(lambda m: m.simulatorState.data & 1 == 0)
        self.assertEqual(info_seq(stopped), -1)
        # stopped at the defaults: state 0, as V-REP (its real-time switch is off by default)
        self.assertEqual(stopped.simulatorState.data, 0)
        self.assertEqual(call("simRosGetInfo").simulatorState, 0)
        self.assertEqual(call("simRosPauseSimulation").result, 0)
        self.assertEqual(call("simRosStopSimulation").result, 0)
        self.assertEqual(call("simRosStartSimulation").result, 1)
        self.wait_info(lambda m: m.simulatorState.data & 1 == 1 and info_seq(m) >= 0)
        info = call("simRosGetInfo")
        self.assertEqual(info.simulatorState & 4, 0)      # the real-time switch: off (V-REP's)
        self.assertAlmostEqual(info.timeStep, 0.05, places=6)
        realtime = vc.BOOLPARAM_REALTIME_SIMULATION
        try:
            self.assertEqual(call("simRosSetBooleanParameter", parameter=realtime,
                                  parameterValue=1).result, 1)
            self.assertEqual(call("simRosGetInfo").simulatorState & 4, 4)
            self.wait_info(lambda m: m.simulatorState.data & 4 == 4)
        finally:
            call("simRosSetBooleanParameter", parameter=realtime, parameterValue=0)
        self.assertEqual(call("simRosGetInfo").simulatorState & 4, 0)

    # --- signals, parameters, selection, errors -------------------------------------------------
    def test_signals(self):
        self.assertEqual(call("simRosSetIntegerSignal", signalName="i", signalValue=7).result, 1)
        self.assertEqual(call("simRosGetIntegerSignal", signalName="i").signalValue, 7)
        self.assertEqual(call("simRosGetIntegerSignal", signalName="missing").result, 0)
        self.assertEqual(call("simRosSetFloatSignal", signalName="f", signalValue=0.5).result, 1)
        self.assertEqual(call("simRosGetFloatSignal", signalName="f").signalValue, 0.5)
        self.assertEqual(call("simRosSetFloatSignal", signalName="f",
                              signalValue=math.nan).result, -1)
        self.assertEqual(call("simRosSetStringSignal", signalName="s",
                              signalValue="abc").result, 1)
        self.assertEqual(call("simRosGetStringSignal", signalName="s").signalValue, "abc")
        taken = call("simRosGetAndClearStringSignal", signalName="s")
        self.assertEqual((taken.result, taken.signalValue), (1, "abc"))
        self.assertEqual(call("simRosGetStringSignal", signalName="s").result, -1)
        self.assertEqual(call("simRosClearIntegerSignal", signalName="i").result, 1)
        self.assertEqual(call("simRosClearFloatSignal", signalName="").result, 1)   # all
        self.assertEqual(call("simRosSetStringSignal", signalName="", signalValue="x").result, -1)

    def test_parameters_and_selection(self):
        self.assertEqual(call("simRosGetIntegerParameter", parameter=1).parameterValue, 30300)
        # the real-time switch: off, V-REP's default (the pace is rtf's)
        self.assertEqual(call("simRosGetBooleanParameter",
                              parameter=vc.BOOLPARAM_REALTIME_SIMULATION).parameterValue, 0)
        self.assertEqual(call("simRosGetBooleanParameter", parameter=9999).parameterValue, -1)
        self.assertAlmostEqual(call("simRosGetFloatingParameter", parameter=1).parameterValue,
                               0.05, places=6)
        gravity = call("simRosGetArrayParameter", parameter=0)
        self.assertEqual(gravity.result, 1)
        self.assertLess(gravity.parameterValues[2], -9.0)
        self.assertEqual(call("simRosSetFloatingParameter", parameter=1,
                              parameterValue=0.01).result, -1)                 # not stopped
        a, b = handle("ePuck"), handle("ePuck_camera#0")
        self.assertEqual(call("simRosSetObjectSelection", handles=[a, 99999, b]).result, 2)
        self.assertEqual(list(call("simRosGetObjectSelection").handles), [a, b])

    def test_failure_answers_are_recorded_in_last_errors(self):
        self.assertEqual(handle("no_such_object"), -1)
        self.assertEqual(call("simRosGetObjectPose", handle=99999,
                              relativeToObjectHandle=WORLD).result, -1)
        self.assertEqual(call("simRosSetJointTargetVelocity", handle=handle("ePuck_leftJoint"),
                              targetVelocity=math.nan).result, -1)
        self.assertEqual(self.set_base_pose("ePuck#0", math.nan, 0.0, 0.0), -1)
        self.assertEqual(call("simRosGetJointState", handle=handle("ePuck")).result, -1)
        self.assertEqual(call("simRosLoadModel", fileName="x.ttm").result, -1)
        self.assertEqual(call("simRosDisplayDialog").dialogHandle, -1)
        self.assertEqual(call("simRosAddStatusbarMessage", message="hello").result, 1)
        errors = self.last_errors()
        self.assertEqual(len(errors), 7)
        self.assertTrue(errors[0].startswith("simRosGetObjectHandle: "))
        self.assertTrue(any(e.startswith("simRosLoadModel: model file 'x.ttm' is not known "
                                          "(models: ") and "ePuck.ttm, e-puck.ttm" in e
                            for e in errors), errors)
        self.assertIn("simRosDisplayDialog is not supported by this simulator (no dialogs)",
                      errors)
        self.assertEqual(self.last_errors(), [])                          # emptied when read

    def test_every_advertised_service_answers(self):
        state = rosgraph.masterapi.Master("/test_vrep_services").getSystemState()
        advertised = sorted(s for s, _ in state[2] if s.startswith("/vrep/simRos"))
        expected = sorted("/vrep/" + n for n in dir(vrep_common.srv)
                          if n.startswith("simRos") and not n.endswith(("Request", "Response"))
                          and n not in NOT_ADVERTISED)
        self.assertEqual(len(expected), 96)
        self.assertEqual(advertised, expected)
        try:
            for name in expected:
                answer = {}
                worker = threading.Thread(
                    target=lambda n=name: answer.setdefault("r", call(n.split("/")[-1])),
                    daemon=True)
                worker.start()
                worker.join(timeout=5.0)
                self.assertIn("r", answer, f"{name} did not answer within 5 s")
        finally:
            call("simRosSynchronous", enable=0)
            call("simRosStartSimulation")
        self.assertEqual([e for e in self.guard.errors if "/vrep" in e], [])
        wait_sim_time(0.2)


if __name__ == "__main__":
    rostest.rosrun(PKG, "test_vrep_services", VrepServices)
