// floor_sender: the per-message floor of the swarm benchmark's scenario (b). A bare roscpp
// process advertises what the simulator advertises for N robots in the vrep profile (8 IR
// Range topics, the IMU, ground truth, a 40x40 rgb8 camera at 4 frames per simulated second,
// /tf with the moving frames, /clock) and publishes one 50 ms "step" of those messages after
// another, as fast as it can, with no simulation at all. With bench/subscribe_all subscribed
// to everything, its steps per wall second say what the kernel and roscpp's transport alone
// allow over the same connections; the simulator's (b) is measured against it.
//
// Usage: floor_sender [--robots N] [--duration S]
// After --duration wall seconds (or on SIGINT) it prints one JSON line:
//   {"sender":"floor_cpp","robots":N,"steps":s,"wall_s":t,"rtf":s*0.05/t}
#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/Range.h>
#include <tf2_msgs/TFMessage.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace {

constexpr double kStepS = 0.05;
constexpr int kCameraEverySteps = 5;  // 4 frames per simulated second at 50 ms steps

volatile std::sig_atomic_t g_stop = 0;
void requestStop(int /*signal*/) { g_stop = 1; }

/// One robot's per-step publishers and messages.
struct Robot {
  std::vector<ros::Publisher> ranges;
  ros::Publisher imu, ground_truth, camera;
  sensor_msgs::Range range_msg;
  sensor_msgs::Imu imu_msg;
  nav_msgs::Odometry odom_msg;
  sensor_msgs::Image image_msg;
};

Robot advertise(ros::NodeHandle& node, int index) {
  const std::string name = "/ePuck" + std::to_string(index);
  Robot robot;
  for (int k = 0; k < 8; ++k) {
    robot.ranges.push_back(
        node.advertise<sensor_msgs::Range>(name + "/proximity" + std::to_string(k), 1));
  }
  robot.imu = node.advertise<sensor_msgs::Imu>(name + "/imu", 1);
  robot.ground_truth = node.advertise<nav_msgs::Odometry>(name + "/ground_truth", 1);
  robot.camera = node.advertise<sensor_msgs::Image>(name + "/camera", 1);
  robot.range_msg.header.frame_id = name.substr(1) + "/base_prox0";
  robot.range_msg.max_range = 0.05f;
  robot.imu_msg.header.frame_id = name.substr(1) + "/base_link";
  robot.odom_msg.header.frame_id = "odom";
  robot.odom_msg.child_frame_id = name.substr(1) + "/base_link";
  robot.image_msg.header.frame_id = name.substr(1) + "/camera_optical";
  robot.image_msg.width = robot.image_msg.height = 40;
  robot.image_msg.encoding = "rgb8";
  robot.image_msg.step = 120;
  robot.image_msg.data.assign(40 * 120, 128);
  return robot;
}

/// The moving frames of every robot, as the simulator's /tf: base_link and both wheels.
tf2_msgs::TFMessage transforms(int robots) {
  tf2_msgs::TFMessage msg;
  for (int i = 0; i < robots; ++i) {
    const std::string base = "ePuck" + std::to_string(i) + "/base_link";
    for (const std::string& child : {base, base + "_left_wheel", base + "_right_wheel"}) {
      geometry_msgs::TransformStamped t;
      t.header.frame_id = child == base ? "odom" : base;
      t.child_frame_id = child;
      t.transform.rotation.w = 1.0;
      msg.transforms.push_back(t);
    }
  }
  return msg;
}

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "floor_sender", ros::init_options::NoSigintHandler);
  int robots = 100;
  double duration_s = 10.0;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--robots") robots = std::atoi(argv[i + 1]);
    else if (flag == "--duration") duration_s = std::atof(argv[i + 1]);
  }
  if (robots < 1 || !(duration_s > 0.0)) {
    std::fprintf(stderr, "usage: floor_sender [--robots N>0] [--duration S>0]\n");
    return 2;
  }
  std::signal(SIGINT, requestStop);
  std::signal(SIGTERM, requestStop);
  ros::NodeHandle node;
  std::vector<Robot> swarm;
  for (int i = 0; i < robots; ++i) swarm.push_back(advertise(node, i));
  ros::Publisher tf = node.advertise<tf2_msgs::TFMessage>("/tf", 1);
  ros::Publisher clock = node.advertise<rosgraph_msgs::Clock>("/clock", 1);
  tf2_msgs::TFMessage tf_msg = transforms(robots);
  ros::AsyncSpinner spinner(1);
  spinner.start();
  const auto start = std::chrono::steady_clock::now();
  long steps = 0;
  double wall_s = 0.0;
  while (!g_stop && ros::ok() && wall_s < duration_s) {
    const ros::Time stamp(steps * kStepS);
    for (Robot& robot : swarm) {
      robot.range_msg.header.stamp = robot.imu_msg.header.stamp = stamp;
      for (ros::Publisher& p : robot.ranges) p.publish(robot.range_msg);
      robot.imu.publish(robot.imu_msg);
      robot.odom_msg.header.stamp = stamp;
      robot.ground_truth.publish(robot.odom_msg);
      if (steps % kCameraEverySteps == 0) {
        robot.image_msg.header.stamp = stamp;
        robot.camera.publish(robot.image_msg);
      }
    }
    tf.publish(tf_msg);
    rosgraph_msgs::Clock now;
    now.clock = stamp;
    clock.publish(now);
    ++steps;
    wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  std::printf("{\"sender\":\"floor_cpp\",\"robots\":%d,\"steps\":%ld,\"wall_s\":%.3f,\"rtf\":%.3f}\n",
              robots, steps, wall_s, steps * kStepS / wall_s);
  std::fflush(stdout);
  ros::shutdown();
  return 0;
}
