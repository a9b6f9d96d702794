// enki_swarm: Enki's C++ library driven from C++, the strongest peer of the swarm benchmark.
//
// N e-pucks with their 8 IR sensors (CAPABILITY_BASIC_SENSORS: no linear camera, unlike
// Debian's Python binding, which always builds one), each avoiding obstacles with the same
// Braitenberg rule as bench/enki_peer.py, in C++ (Enki calls controlStep for every robot in
// World::step). The robots start on a grid, one per --cell-m square cell, in a walled square
// arena; headings come from a seeded generator. With --worlds B, B such worlds are stepped one
// after the other (bench/learn_bench.py's batched task); with --cylinders C, each world also
// holds C static cylinders placed as learn_bench.py places them (cylinder_centres below).
//
// Timed: World::step(step) with Enki's single physics pass, after --warmup-seconds of
// simulated time. "startup_s" runs from the start of main to the end of the first step
// (building the world and its robots, then one step), the figure a user waits for.
//
// Usage: enki_swarm [--robots N] [--step S] [--sim-seconds T] [--warmup-seconds W]
//                   [--cell-m C] [--seed K] [--worlds B] [--cylinders C]
// Prints one JSON line to stdout:
//   {"peer":"enki_cpp","robots":N,"step_s":S,"sim_s":..,"wall_s":..,"rtf":..,
//    "startup_s":..,"peak_rss_mb":..,"cell_m":C,"seed":K,"worlds":B,"cylinders":C,
//    "rss_growth_mb":..}   (rss_growth_mb: resident memory added by building and first stepping
//    the worlds)
// Enki works in centimetres; this program speaks metres and converts once, at the boundary.

#include <enki/PhysicalEngine.h>
#include <enki/robots/e-puck/EPuck.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;

constexpr double kCmPerM = 100.0;
constexpr double kArenaMarginM = 0.10;
constexpr double kMaxSpeedMS = 0.128;
// The rule of bench/enki_peer.py: x_i = min(ir_i / kIrSaturation, 1) and each wheel turns at
//   v = kCruiseMS + kAvoidGainMS * sum_i w_i x_i  (m/s), clamped to the motor limit.
constexpr double kIrSaturation = 300.0;
constexpr double kCruiseMS = 0.08;
constexpr double kAvoidGainMS = 0.4;
constexpr double kLeftWeights[8] = {-1.0, -0.8, -0.4, 0.0, 0.0, 0.4, 0.8, 1.2};
constexpr double kRightWeights[8] = {1.0, 0.8, 0.4, 0.0, 0.0, -0.4, -0.8, -1.2};

struct Options {
  int robots = 1;
  double step_s = 0.01;
  double sim_s = 20.0;
  double warmup_s = 1.0;
  double cell_m = 0.30;
  unsigned long seed = 1;
  int worlds = 1;
  int cylinders = 0;
};

// Static cylinders of the batched task, one world's: cylinder k stands 10 cm from the centre of
// cell (7 k mod N) along the cell's diagonal, up-right for even k, down-left for odd k.
constexpr double kCylinderRadiusM = 0.02;
constexpr double kCylinderHeightM = 0.08;
constexpr double kCylinderOffsetM = 0.10;

double clampSpeed(double speed_m_s) {
  return std::max(-kMaxSpeedMS, std::min(kMaxSpeedMS, speed_m_s));
}

/// An e-puck whose controlStep turns its eight IR values into wheel speeds, then lets
/// DifferentialWheeled apply them.
class BraitenbergEPuck : public Enki::EPuck {
 public:
  BraitenbergEPuck() : Enki::EPuck(CAPABILITY_BASIC_SENSORS) {}

  void controlStep(double dt) override {
    const Enki::IRSensor* sensors[8] = {&infraredSensor0, &infraredSensor1, &infraredSensor2,
                                        &infraredSensor3, &infraredSensor4, &infraredSensor5,
                                        &infraredSensor6, &infraredSensor7};
    double left = 0.0;
    double right = 0.0;
    for (int i = 0; i < 8; ++i) {
      const double x = std::min(sensors[i]->getValue() / kIrSaturation, 1.0);
      left += kLeftWeights[i] * x;
      right += kRightWeights[i] * x;
    }
    leftSpeed = clampSpeed(kCruiseMS + kAvoidGainMS * left) * kCmPerM;
    rightSpeed = clampSpeed(kCruiseMS + kAvoidGainMS * right) * kCmPerM;
    Enki::EPuck::controlStep(dt);
  }
};

[[noreturn]] void usage(const char* program) {
  std::fprintf(stderr,
               "usage: %s [--robots N] [--step S] [--sim-seconds T] [--warmup-seconds W] "
               "[--cell-m C] [--seed K] [--worlds B] [--cylinders C]\n",
               program);
  std::exit(2);
}

Options parseOptions(int argc, char** argv) {
  Options options;
  for (int i = 1; i < argc; ++i) {
    if (i + 1 >= argc) usage(argv[0]);
    const std::string flag = argv[i];
    const char* value = argv[++i];
    if (flag == "--robots") options.robots = std::atoi(value);
    else if (flag == "--step") options.step_s = std::atof(value);
    else if (flag == "--sim-seconds") options.sim_s = std::atof(value);
    else if (flag == "--warmup-seconds") options.warmup_s = std::atof(value);
    else if (flag == "--cell-m") options.cell_m = std::atof(value);
    else if (flag == "--seed") options.seed = std::strtoul(value, nullptr, 10);
    else if (flag == "--worlds") options.worlds = std::atoi(value);
    else if (flag == "--cylinders") options.cylinders = std::atoi(value);
    else usage(argv[0]);
  }
  if (options.robots < 1 || options.worlds < 1 || options.cylinders < 0 || !(options.step_s > 0.0) || !(options.sim_s > 0.0) ||
      options.warmup_s < 0.0 || !(options.cell_m > 0.0)) {
    usage(argv[0]);
  }
  return options;
}

/// A walled square arena, robots on a grid (the world owns and deletes them).
std::unique_ptr<Enki::World> buildWorld(const Options& options) {
  const int per_row = static_cast<int>(std::ceil(std::sqrt(options.robots)));
  const double side_m = options.cell_m * per_row + kArenaMarginM;
  auto world = std::make_unique<Enki::World>(side_m * kCmPerM, side_m * kCmPerM);
  world->setRandomSeed(options.seed);
  std::mt19937 headings(static_cast<std::mt19937::result_type>(options.seed));
  std::uniform_real_distribution<double> heading(-M_PI, M_PI);
  for (int index = 0; index < options.robots; ++index) {
    auto* robot = new BraitenbergEPuck();
    const int row = index / per_row;
    const int column = index % per_row;
    robot->pos = Enki::Point((kArenaMarginM / 2 + (column + 0.5) * options.cell_m) * kCmPerM,
                             (kArenaMarginM / 2 + (row + 0.5) * options.cell_m) * kCmPerM);
    robot->angle = heading(headings);
    world->addObject(robot);
  }
  for (int k = 0; k < options.cylinders; ++k) {
    const int cell = static_cast<int>((7L * k) % options.robots);
    const double sign = k % 2 == 0 ? 1.0 : -1.0;
    auto* cylinder = new Enki::PhysicalObject();
    cylinder->setCylindric(kCylinderRadiusM * kCmPerM, kCylinderHeightM * kCmPerM, -1.0);
    cylinder->pos = Enki::Point(
        (kArenaMarginM / 2 + (cell % per_row + 0.5) * options.cell_m + sign * kCylinderOffsetM) *
            kCmPerM,
        (kArenaMarginM / 2 + (cell / per_row + 0.5) * options.cell_m + sign * kCylinderOffsetM) *
            kCmPerM);
    world->addObject(cylinder);
  }
  return world;
}

long stepsFor(double sim_s, double step_s) {
  return std::max(1L, std::lround(sim_s / step_s));
}

/// Peak resident memory of this process (VmHWM, MB). Not getrusage's ru_maxrss, which keeps
/// the peak of the process that forked us (a Python benchmark driver) across exec.
double statusMb(const char* field) {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind(field, 0) == 0) return std::atof(line.c_str() + std::strlen(field)) / 1024.0;
  }
  return -1.0;
}

double peakRssMb() { return statusMb("VmHWM:"); }

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace

int main(int argc, char** argv) {
  const Clock::time_point process_start = Clock::now();
  Options options = parseOptions(argc, argv);
  const double rss_before_mb = statusMb("VmRSS:");
  std::vector<std::unique_ptr<Enki::World>> worlds;
  const unsigned long first_seed = options.seed;
  for (int b = 0; b < options.worlds; ++b) {
    options.seed = first_seed + static_cast<unsigned long>(b);
    worlds.push_back(buildWorld(options));
  }
  options.seed = first_seed;
  const auto step_all = [&worlds, &options]() {
    for (auto& world : worlds) world->step(options.step_s);
  };
  step_all();
  const double startup_s = secondsSince(process_start);
  const double rss_growth_mb = statusMb("VmRSS:") - rss_before_mb;
  for (long i = 1; i < stepsFor(options.warmup_s, options.step_s); ++i) step_all();
  const long steps = stepsFor(options.sim_s, options.step_s);
  const Clock::time_point start = Clock::now();
  for (long i = 0; i < steps; ++i) step_all();
  const double wall_s = secondsSince(start);
  const double timed_sim_s = steps * options.step_s;
  std::printf(
      "{\"peer\":\"enki_cpp\",\"robots\":%d,\"step_s\":%g,\"sim_s\":%.9g,\"wall_s\":%.6f,"
      "\"rtf\":%.6f,\"startup_s\":%.6f,\"peak_rss_mb\":%.1f,\"cell_m\":%g,\"seed\":%lu,"
      "\"worlds\":%d,\"cylinders\":%d,\"rss_growth_mb\":%.3f}\n",
      options.robots, options.step_s, timed_sim_s, wall_s, timed_sim_s / wall_s, startup_s,
      peakRssMb(), options.cell_m, options.seed, options.worlds, options.cylinders,
      rss_growth_mb);
  return 0;
}
