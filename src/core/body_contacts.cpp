#include "epuck_vrep_compat/body_contacts.hpp"

#include <algorithm>
#include <unordered_map>

namespace evc {
namespace {

// Extends the planar move so it covers `depth` along `normal`; returns false for a contact
// whose normal is (nearly) vertical, which no move in the plane can resolve.
bool cover(const Vec3& normal, double depth, Eigen::Vector2d& move) {
  Eigen::Vector2d planar(normal.x(), normal.y());
  const double length = planar.norm();
  if (length < 1e-6) return false;
  planar /= length;
  const double missing = depth - move.dot(planar);
  if (missing > 0.0) move += missing * planar;
  return true;
}

// Between two listed bodies (upright cylinders) the exact normal is the line between their
// axes. Bullet's EPA normal is off by ~3e-4 rad in deep contacts, enough to let two robots
// pushing nose to nose creep sideways and slip past each other.
Vec3 centre_line(const MovableBody& self, const MovableBody& other, const Vec3& fallback) {
  Vec3 line = self.pose.position_m - other.pose.position_m;
  line.z() = 0.0;
  const double length = line.norm();
  return length > 1e-9 ? Vec3(line / length) : fallback;
}

void translate(CollisionWorld& world, MovableBody& body, const Eigen::Vector2d& move) {
  body.pose.position_m.x() += move.x();
  body.pose.position_m.y() += move.y();
  world.set_pose(body.handle, body.pose);
}

}  // namespace

double resolve_penetrations(CollisionWorld& world, std::vector<MovableBody>& bodies,
                            const ContactSettings& settings) {
  std::unordered_map<int, size_t> index_of;
  for (size_t i = 0; i < bodies.size(); ++i) index_of.emplace(bodies[i].handle, i);
  std::vector<char> active(bodies.size(), 1);
  std::vector<char> next_active(bodies.size(), 0);
  double deepest = 0.0;
  for (int pass = 0; pass < settings.max_passes; ++pass) {
    deepest = 0.0;
    std::fill(next_active.begin(), next_active.end(), 0);
    for (size_t i = 0; i < bodies.size(); ++i) {
      if (!active[i]) continue;
      Eigen::Vector2d move = Eigen::Vector2d::Zero();
      for (const Contact& contact : world.contacts(bodies[i].handle)) {
        deepest = std::max(deepest, contact.depth_m);
        const auto other = index_of.find(contact.other_handle);
        const bool shared = other != index_of.end();
        const double share = shared ? 0.5 : 1.0;
        const Vec3 normal =
            shared ? centre_line(bodies[i], bodies[other->second], contact.normal) : contact.normal;
        if (!cover(normal, share * contact.depth_m + settings.slop_m, move)) continue;
        if (shared) {
          Eigen::Vector2d other_move = Eigen::Vector2d::Zero();
          cover(-normal, share * contact.depth_m + settings.slop_m, other_move);
          translate(world, bodies[other->second], other_move);
          next_active[other->second] = 1;
        }
      }
      if (!move.isZero()) {
        translate(world, bodies[i], move);
        next_active[i] = 1;
      }
    }
    if (deepest <= settings.tolerance_m) break;
    active.swap(next_active);
  }
  return deepest;
}

}  // namespace evc
