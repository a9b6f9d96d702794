// CollisionWorld::ray_cast in C++ alone: the closed-form hits on a box (face, slanted, a
// yawed corner) and a sphere give the analytic distances and normals; a ray that reaches
// nothing reports no hit. Moves reach the broadphase lazily (at the next query): a moved or
// teleported object is found where it is and not where it was, by rays, box queries and
// contacts, also by queries on several threads at once; an exact tie goes to the lower handle.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <thread>
#include <vector>

#include "epuck_vrep_compat/world/collision_world.hpp"

namespace {

using evc::CollisionWorld;
using evc::Pose;
using evc::RayHit;
using evc::Vec3;

const Vec3 kGrey(0.5, 0.5, 0.5);
constexpr double kExact = 1e-12;

Pose at(double x_m, double y_m, double z_m, double yaw_rad = 0.0) {
  Pose pose;
  pose.position_m = Vec3(x_m, y_m, z_m);
  pose.orientation = evc::Quat(Eigen::AngleAxisd(yaw_rad, Vec3::UnitZ()));
  return pose;
}

Vec3 heading(double yaw_rad) { return Vec3(std::cos(yaw_rad), std::sin(yaw_rad), 0.0); }

/// One ray (the single-ray overload; Eigen's expressions would also fit the batched one).
RayHit cast(const CollisionWorld& world, const Vec3& origin, const Vec3& direction,
            double max_distance_m = 10.0, int ignore_handle = -1) {
  return world.ray_cast(origin, direction, max_distance_m, ignore_handle);
}

TEST(RayCast, ABoxFaceIsHitAtItsDistanceWithItsNormal) {
  CollisionWorld world;
  world.add_box(7, Vec3(0.01, 0.5, 0.5), at(0.31, 0.0, 0.0), kGrey);  // face at x = 0.3
  const RayHit hit = cast(world, Vec3(0.0, 0.1, 0.2), Vec3::UnitX());
  EXPECT_NEAR(hit.distance_m, 0.3, kExact);
  EXPECT_EQ(hit.handle, 7);
  EXPECT_NEAR((hit.normal - Vec3(-1.0, 0.0, 0.0)).norm(), 0.0, kExact);
  const double slanted = M_PI / 6.0;
  EXPECT_NEAR(cast(world, Vec3::Zero(), heading(slanted)).distance_m,
              0.3 / std::cos(slanted), kExact);
}

TEST(RayCast, AYawedCubeIsHitAtItsCorner) {
  CollisionWorld world;
  world.add_box(1, Vec3(0.1, 0.1, 0.1), at(1.0, 0.0, 0.0, M_PI / 4.0), kGrey);
  EXPECT_NEAR(cast(world, Vec3::Zero(), Vec3::UnitX()).distance_m,
              1.0 - 0.1 * std::sqrt(2.0), kExact);
}

TEST(RayCast, ASphereIsHitWhereTheChordBegins) {
  CollisionWorld world;
  world.add_sphere(3, 0.5, at(2.0, 0.0, 0.0), kGrey);
  // Offset 0.3 from the centre line: the ray enters 2 - sqrt(0.5² - 0.3²) = 1.6 m away.
  const RayHit hit = cast(world, Vec3(0.0, 0.3, 0.0), Vec3::UnitX());
  EXPECT_NEAR(hit.distance_m, 1.6, kExact);
  EXPECT_EQ(hit.handle, 3);
  EXPECT_NEAR((hit.normal - Vec3(-0.8, 0.6, 0.0)).norm(), 0.0, kExact);
}

TEST(RayCast, NothingWithinReachIsNoHit) {
  CollisionWorld world;
  world.add_box(1, Vec3(0.1, 0.1, 0.1), at(1.0, 0.0, 0.0), kGrey);
  for (const RayHit& hit : {cast(world, Vec3::Zero(), Vec3::UnitX(), 0.85),
                            cast(world, Vec3::Zero(), Vec3::UnitY())}) {
    EXPECT_EQ(hit.distance_m, std::numeric_limits<double>::infinity());
    EXPECT_EQ(hit.handle, -1);
  }
  EXPECT_EQ(cast(world, Vec3::Zero(), Vec3::UnitX(), 10.0, 1).handle, -1);  // ignored
}

TEST(RayCast, AnExactTieGoesToTheLowerHandle) {
  CollisionWorld world;
  // Two boxes whose near faces lie in the same plane x = 0.3, added higher handle first, then
  // moved about so that the broadphase tree's order is not the handle order.
  world.add_box(9, Vec3(0.1, 0.1, 0.1), at(0.4, 0.05, 0.0), kGrey);
  world.add_box(4, Vec3(0.1, 0.1, 0.1), at(0.4, -0.05, 0.0), kGrey);
  for (int k = 0; k < 5; ++k) {
    world.set_pose(4, at(3.0 + k, -0.05, 0.0));
    world.maintain_broadphase();
    EXPECT_EQ(cast(world, Vec3::Zero(), Vec3::UnitX()).handle, 9);
    world.set_pose(4, at(0.4, -0.05, 0.0));
    EXPECT_EQ(cast(world, Vec3::Zero(), Vec3::UnitX()).handle, 4);
  }
}

TEST(LazyBroadphase, AMovedObjectIsFoundWhereItIsAndNotWhereItWas) {
  CollisionWorld world;
  world.add_sphere(1, 0.1, at(1.0, 0.0, 0.0), kGrey, evc::kGroupRobot);  // a robot touches
  world.add_sphere(2, 0.1, at(0.0, 5.0, 0.0), kGrey);                     // static objects
  // Several moves before any query, the last one a teleport far from the first place.
  world.set_pose(1, at(1.5, 0.0, 0.0));
  world.set_pose(1, at(40.0, 0.0, 0.0));
  world.set_pose(1, at(0.0, 5.15, 0.0));  // overlaps sphere 2
  EXPECT_EQ(cast(world, Vec3::Zero(), Vec3::UnitX()).handle, -1);
  EXPECT_EQ(cast(world, Vec3(0.0, 4.0, 0.0), Vec3::UnitY()).handle, 2);
  std::vector<const evc::Body*> found;
  world.overlap_query(Vec3(-0.5, -0.5, -0.5), Vec3(2.0, 0.5, 0.5), evc::kGroupAll, -1, found);
  EXPECT_TRUE(found.empty());
  world.overlap_query(Vec3(-0.5, 5.2, -0.5), Vec3(0.5, 5.3, 0.5), evc::kGroupAll, -1, found);
  ASSERT_EQ(found.size(), 1u);
  const std::vector<evc::Contact> contacts = world.contacts(1);
  ASSERT_EQ(contacts.size(), 1u);
  EXPECT_EQ(contacts[0].other_handle, 2);
  // A moved object removed before any query leaves nothing stale behind.
  world.set_pose(2, at(9.0, 9.0, 0.0));
  world.remove(2);
  world.maintain_broadphase();
  EXPECT_EQ(cast(world, Vec3(0.0, 4.0, 0.0), Vec3::UnitY()).handle, 1);
  EXPECT_TRUE(world.contacts(1).empty());
}

TEST(LazyBroadphase, QueriesOnSeveralThreadsAfterMovesAgreeWithOne) {
  CollisionWorld world;
  for (int i = 0; i < 64; ++i) world.add_sphere(i, 0.05, at(0.2 * i, 1.0, 0.0), kGrey);
  for (int i = 0; i < 64; ++i) world.set_pose(i, at(0.2 * i, 1.0 + 0.01 * i, 0.0));
  // Every thread's first query finds the boxes stale; one of them updates them.
  std::vector<std::vector<int>> seen(4, std::vector<int>(64, -2));
  std::vector<std::thread> threads;
  for (std::size_t t = 0; t < seen.size(); ++t) {
    threads.emplace_back([&world, &seen, t] {
      for (int i = 0; i < 64; ++i) seen[t][i] = cast(world, Vec3(0.2 * i, 0.0, 0.0),
                                                     Vec3::UnitY()).handle;
    });
  }
  for (std::thread& thread : threads) thread.join();
  for (const std::vector<int>& handles : seen) {
    for (int i = 0; i < 64; ++i) EXPECT_EQ(handles[i], i);
  }
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
