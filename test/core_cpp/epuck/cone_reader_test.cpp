// A cone's reading is the shortest hit over its rays, the earliest ray on a tie. The reader
// casts few of them (it culls the bodies, starts with the ray that may hit soonest, visits the
// rays of a ring from the one leaning most toward a lone target outward, and skips every ray
// that cannot beat the best so far); none of that may change a reading. Here every reading is
// checked, bit for bit, against the plain answer: every ray of the cone cast through the
// world's broadphase in turn. Scenes of boxes (walls turned or square to the axes, where a
// level sensor's mirrored rays tie), upright cylinders and spheres around sensors at random
// poses, level or tilted; read whole (ConeReader::read) and in two halves with a cull frame
// that differs from the exact one by rounding, as the swarm reads them (cull, read_culled).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "epuck_vrep_compat/epuck/cone_sensor.hpp"
#include "epuck_vrep_compat/random/rng.hpp"
#include "epuck_vrep_compat/world/collision_world.hpp"

namespace {

using evc::ConeReading;
using evc::ConeSensor;
using evc::Pose;
using evc::Quat;
using evc::Vec3;

constexpr double kPi = 3.14159265358979323846;

// Every ray in turn: the shortest hit, the earliest ray on a tie (sensor frame, as the reader).
ConeReading every_ray(const evc::CollisionWorld& world, const Pose& pose,
                      const ConeSensor& sensor, const std::vector<Vec3>& directions) {
  const Eigen::Matrix3d rotation = pose.orientation.toRotationMatrix();
  ConeReading best;
  for (const Vec3& direction : directions) {
    const evc::RayHit hit = world.ray_cast(pose.position_m, rotation * direction,
                                           sensor.max_range_m);
    if (hit.handle < 0 || !(hit.distance_m < best.distance_m)) continue;
    best.distance_m = hit.distance_m;
    best.handle = hit.handle;
    best.point_m = direction * hit.distance_m;
    best.normal = rotation.transpose() * hit.normal;
  }
  return best;
}

bool same(const ConeReading& a, const ConeReading& b) {
  return a.handle == b.handle && a.distance_m == b.distance_m && a.point_m == b.point_m &&
         a.normal == b.normal;
}

// A few bodies within a sensor's reach of the origin.
void fill(evc::CollisionWorld& world, evc::Rng& rng) {
  const auto between = [&](double low, double high) { return low + (high - low) * rng.uniform(); };
  const int count = 1 + static_cast<int>(rng.uniform() * 4);
  for (int handle = 1; handle <= count; ++handle) {
    const double kind = rng.uniform();
    const double yaw = rng.uniform() < 0.5 ? 0.0 : between(-kPi, kPi);  // square or turned
    const Pose pose{Vec3(between(-0.07, 0.07), between(-0.07, 0.07), between(0.0, 0.06)),
                    Quat(Eigen::AngleAxisd(yaw, Vec3::UnitZ()))};
    if (kind < 0.5) {  // a wall or a block
      world.add_box(handle, Vec3(between(0.002, 0.08), between(0.002, 0.02), between(0.01, 0.05)),
                    pose, Vec3::Ones());
    } else if (kind < 0.85) {
      world.add_cylinder(handle, between(0.005, 0.04), between(0.02, 0.1), pose, Vec3::Ones());
    } else {
      world.add_sphere(handle, between(0.005, 0.03), pose, Vec3::Ones());
    }
  }
}

TEST(ConeReader, ReadsWhatEveryRayWouldRead) {
  ConeSensor wide;
  wide.half_angle_rad = 0.45;
  wide.max_range_m = 0.08;
  wide.rings = 3;
  wide.azimuths = 8;
  const std::vector<ConeSensor> sensors{ConeSensor(), wide};
  evc::Rng rng(20261127);
  evc::ConeReader reader;
  int readings = 0, hits = 0, ties = 0;
  for (int scene = 0; scene < 1000; ++scene) {
    evc::CollisionWorld world;
    fill(world, rng);
    std::vector<evc::ConeCandidate> candidates;
    for (const evc::Body* body : world.bodies_in_handle_order()) {
      candidates.push_back(evc::cone_candidate(*body));
    }
    for (int trial = 0; trial < 20; ++trial) {
      const ConeSensor& sensor = sensors[trial % 2];
      const std::vector<Vec3> directions = evc::cone_ray_directions(sensor);
      const bool level = trial % 4 < 2;  // yaw alone, at a height of the e-puck's sensors
      const double yaw = (rng.uniform() * 2.0 - 1.0) * kPi;
      Quat orientation(Eigen::AngleAxisd(yaw, Vec3::UnitZ()));
      if (!level) {
        orientation = orientation * Quat(Eigen::AngleAxisd(rng.uniform() - 0.5, Vec3::UnitY())) *
                      Quat(Eigen::AngleAxisd(rng.uniform() - 0.5, Vec3::UnitX()));
      }
      const Pose pose{Vec3(0.04 * (rng.uniform() * 2.0 - 1.0), 0.04 * (rng.uniform() * 2.0 - 1.0),
                           level ? 0.034 : 0.06 * rng.uniform()),
                      orientation};
      // Half-spaces seen from elsewhere, as a robot's centre sees them for all its cones.
      const Vec3 viewpoint = pose.position_m - 0.03 * (orientation * Vec3::UnitX());
      for (evc::ConeCandidate& candidate : candidates) evc::bound_candidate(candidate, viewpoint);
      const ConeReading expected = every_ray(world, pose, sensor, directions);
      const ConeReading whole = reader.read(candidates, pose, sensor, directions);
      ConeReading halves;
      // The swarm's cull frame: the axis from the rotation matrix, which rounds otherwise.
      const Eigen::Matrix3d frame = orientation.toRotationMatrix();
      if (reader.cull(candidates, pose.position_m, frame.col(0), sensor)) {
        halves = reader.read_culled(pose, sensor, directions);
      }
      EXPECT_TRUE(same(whole, expected)) << "scene " << scene << " trial " << trial;
      EXPECT_TRUE(same(halves, expected)) << "scene " << scene << " trial " << trial;
      ++readings;
      hits += expected.handle >= 0;
      // A tie between two rays (the mirrored rays of a level sensor facing a wall).
      int tied = 0;
      for (const Vec3& direction : directions) {
        tied += expected.handle >= 0 &&
                world.ray_cast(pose.position_m, frame * direction, sensor.max_range_m)
                        .distance_m == expected.distance_m;
      }
      ties += tied > 1;
    }
  }
  // The scenes must test something: a third of the cones or more see a body, and one reading
  // in twenty or more is a tie.
  EXPECT_GT(hits, readings / 3) << hits << " of " << readings;
  EXPECT_GT(ties, readings / 20) << ties << " ties in " << readings;
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
