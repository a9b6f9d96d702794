// A roscpp client of the /vrep simRos* services, written as V-REP-era C++ clients were
// (rosBubbleRob style: ros::service::call on vrep_common types), run against the simulator on
// test/worlds/vrep_services.yaml. It checks that the C++ types (MD5 sums) match and that the
// answers are V-REP's.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <ros/ros.h>
#include <vrep_common/simRosGetJointState.h>
#include <vrep_common/simRosGetLastErrors.h>
#include <vrep_common/simRosGetObjectGroupData.h>
#include <vrep_common/simRosGetObjectHandle.h>
#include <vrep_common/simRosGetObjectPose.h>
#include <vrep_common/simRosLoadModel.h>
#include <vrep_common/simRosSetJointTargetVelocity.h>
#include <vrep_common/simRosSetObjectPose.h>
#include <vrep_common/simRosStartSimulation.h>

namespace {

constexpr int kWorld = -1;
constexpr int kAllObjects = 109;   // sim_appobj_object_type
constexpr int kJointType = 1;      // sim_object_joint_type
const char* const kServicesUsed[] = {
    "simRosGetJointState", "simRosGetLastErrors", "simRosGetObjectGroupData",
    "simRosGetObjectHandle", "simRosGetObjectPose", "simRosLoadModel",
    "simRosSetJointTargetVelocity", "simRosSetObjectPose", "simRosStartSimulation"};

template <typename Service>
Service call(const std::string& name, Service srv = Service()) {
  EXPECT_TRUE(ros::service::call("/vrep/" + name, srv)) << name << " failed";
  return srv;
}

int handle(const std::string& object_name) {
  vrep_common::simRosGetObjectHandle srv;
  srv.request.objectName = object_name;
  return call("simRosGetObjectHandle", srv).response.handle;
}

void setWheelSpeeds(const std::string& suffix, double rad_s) {
  for (const char* side : {"left", "right"}) {
    vrep_common::simRosSetJointTargetVelocity srv;
    srv.request.handle = handle(std::string("ePuck_") + side + "Joint" + suffix);
    srv.request.targetVelocity = rad_s;
    EXPECT_EQ(call("simRosSetJointTargetVelocity", srv).response.result, 1);
  }
}

class VrepCppClient : public ::testing::Test {
 protected:
  void SetUp() override {
    for (const char* name : kServicesUsed) {
      ASSERT_TRUE(ros::service::waitForService(std::string("/vrep/") + name,
                                               ros::Duration(30.0))) << name;
    }
    call<vrep_common::simRosStartSimulation>("simRosStartSimulation");
    call<vrep_common::simRosGetLastErrors>("simRosGetLastErrors");
  }
};

TEST_F(VrepCppClient, HandlesByName) {
  const int left = handle("ePuck_leftJoint");
  const int sensor = handle("ePuck_proxSensor0#0");
  EXPECT_GT(left, 0);
  EXPECT_GT(sensor, 0);
  EXPECT_NE(left, handle("ePuck_leftJoint#0"));
  EXPECT_EQ(handle("no_such_object"), -1);
}

TEST_F(VrepCppClient, GroupDataOfEveryJoint) {
  vrep_common::simRosGetObjectGroupData names;
  names.request.objectType = kJointType;
  names.request.dataType = 0;
  names = call("simRosGetObjectGroupData", names);
  const std::vector<std::string> expected = {"ePuck_leftJoint", "ePuck_rightJoint",
                                             "ePuck_leftJoint#0", "ePuck_rightJoint#0"};
  EXPECT_EQ(names.response.strings, expected);
  ASSERT_EQ(names.response.handles.size(), 4u);
  EXPECT_EQ(names.response.handles[0], handle("ePuck_leftJoint"));

  vrep_common::simRosGetObjectGroupData all;
  all.request.objectType = kAllObjects;
  all.request.dataType = 3;  // absolute positions
  all = call("simRosGetObjectGroupData", all);
  EXPECT_GT(all.response.handles.size(), 40u);
  EXPECT_EQ(all.response.floatData.size(), 3 * all.response.handles.size());
}

TEST_F(VrepCppClient, PoseRoundTrip) {
  setWheelSpeeds("#0", 0.0);
  vrep_common::simRosSetObjectPose set;
  set.request.handle = handle("ePuck#0");
  set.request.relativeToObjectHandle = kWorld;
  set.request.pose.position.x = 0.1;
  set.request.pose.position.y = 0.25;
  set.request.pose.orientation.z = std::sin(0.3);
  set.request.pose.orientation.w = std::cos(0.3);  // yaw 0.6
  EXPECT_EQ(call("simRosSetObjectPose", set).response.result, 1);

  vrep_common::simRosGetObjectPose get;
  get.request.handle = set.request.handle;
  get.request.relativeToObjectHandle = kWorld;
  get = call("simRosGetObjectPose", get);
  ASSERT_EQ(get.response.result, 1);
  const auto& pose = get.response.pose.pose;
  EXPECT_NEAR(pose.position.x, 0.1, 1e-4);
  EXPECT_NEAR(pose.position.y, 0.25, 1e-4);
  EXPECT_NEAR(2.0 * std::atan2(pose.orientation.z, pose.orientation.w), 0.6, 1e-4);
}

TEST_F(VrepCppClient, JointTargetVelocity) {
  setWheelSpeeds("#0", 4.0);
  ros::WallDuration(1.0).sleep();
  vrep_common::simRosGetJointState state;
  state.request.handle = handle("ePuck_leftJoint#0");
  state = call("simRosGetJointState", state);
  setWheelSpeeds("#0", 0.0);
  ASSERT_EQ(state.response.result, 1);
  ASSERT_EQ(state.response.state.velocity.size(), 1u);
  EXPECT_NEAR(state.response.state.velocity[0], 4.0, 1.0);  // actual speed: 5 % slip per step
  EXPECT_EQ(state.response.state.name[0], "ePuck_leftJoint#0");
}

TEST_F(VrepCppClient, FailureAnswersAndLastErrors) {
  EXPECT_EQ(handle("no_such_object"), -1);
  vrep_common::simRosLoadModel load;
  load.request.fileName = "no_such_model.ttm";
  load = call("simRosLoadModel", load);
  EXPECT_EQ(load.response.result, -1);
  vrep_common::simRosSetJointTargetVelocity nan_speed;
  nan_speed.request.handle = handle("ePuck_leftJoint");
  nan_speed.request.targetVelocity = std::nan("");
  EXPECT_EQ(call("simRosSetJointTargetVelocity", nan_speed).response.result, -1);

  const auto errors = call<vrep_common::simRosGetLastErrors>("simRosGetLastErrors").response;
  EXPECT_EQ(errors.errorCnt, 3);
  // V-REP's format: every message followed by a NUL
  std::vector<std::string> messages;
  std::string::size_type start = 0, end;
  while ((end = errors.errorStrings.find('\0', start)) != std::string::npos) {
    messages.push_back(errors.errorStrings.substr(start, end - start));
    start = end + 1;
  }
  ASSERT_EQ(messages.size(), 3u);
  EXPECT_EQ(messages[0].rfind("simRosGetObjectHandle: ", 0), 0u);
  EXPECT_EQ(messages[1].rfind("simRosLoadModel: model file 'no_such_model.ttm' is not known "
                              "(models: ", 0), 0u);
  EXPECT_NE(messages[1].find("ePuck.ttm, e-puck.ttm"), std::string::npos);
  EXPECT_EQ(call<vrep_common::simRosGetLastErrors>("simRosGetLastErrors").response.errorCnt, 0);
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "vrep_cpp_client");
  ros::NodeHandle node;  // keeps the node alive for the whole run
  return RUN_ALL_TESTS();
}
