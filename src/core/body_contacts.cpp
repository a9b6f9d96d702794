#include "epuck_vrep_compat/body_contacts.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "body.hpp"
#include "epuck_vrep_compat/planar_contacts.hpp"

namespace evc {
namespace {

// A shape counts as upright when its local z axis leans less than this (radians) off world z:
// the tilt moves a 5 cm tall wall's faces by 50 pm at most.
constexpr double kUprightTolerance = 1e-9;
// Neighbour lists reach this far beyond a body, so they stay valid until some body has moved
// half of it; larger means fewer rebuilds and more candidates per test.
constexpr double kNeighbourMargin_m = 0.01;

// The prism a body is in the ground plane, when it is one: an upright cylinder or box.
struct PlanarShape {
  enum class Kind { kOther, kCircle, kRectangle };
  Kind kind = Kind::kOther;
  UprightCircle circle;
  UprightRectangle rectangle;
};

PlanarShape planar_shape(const Body& body) {
  PlanarShape shape;
  const btTransform& transform = body.object->getWorldTransform();
  const btMatrix3x3& basis = transform.getBasis();
  if (body.primitive.kind == Primitive::Kind::kSphere ||
      std::abs(basis[0][2]) > kUprightTolerance || std::abs(basis[1][2]) > kUprightTolerance) {
    return shape;
  }
  const btVector3& centre = transform.getOrigin();
  const Eigen::Vector2d centre_m(centre.x(), centre.y());
  if (body.primitive.kind == Primitive::Kind::kCylinder) {
    const double half_height_m = body.primitive.half_height_m;
    shape.kind = PlanarShape::Kind::kCircle;
    shape.circle = UprightCircle{centre_m, body.primitive.radius_m, centre.z() - half_height_m,
                                 centre.z() + half_height_m};
  } else {
    const btVector3& half = body.primitive.half_extents;
    shape.kind = PlanarShape::Kind::kRectangle;
    shape.rectangle = UprightRectangle{centre_m,
                                       Eigen::Vector2d(basis[0][0], basis[1][0]),
                                       Eigen::Vector2d(basis[0][1], basis[1][1]),
                                       Eigen::Vector2d(half.x(), half.y()),
                                       centre.z() - half.z(), centre.z() + half.z()};
  }
  return shape;
}

bool boxes_overlap(const Vec3& min_a, const Vec3& max_a, const btVector3& min_b,
                   const btVector3& max_b) {
  for (int axis = 0; axis < 3; ++axis) {
    if (min_a[axis] > max_b[axis] || min_b[axis] > max_a[axis]) return false;
  }
  return true;
}

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

// The contacts of the listed bodies, analytic where both shapes are upright prisms.
class ContactFinder {
 public:
  ContactFinder(CollisionWorld& world, const std::vector<MovableBody>& bodies)
      : world_(world), self_(bodies.size(), nullptr), drift_m_(bodies.size(), Eigen::Vector2d::Zero()) {
    std::vector<const Body*> found;
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      handles_.push_back(bodies[i].handle);
      const Vec3 centre = world.get_pose(bodies[i].handle).position_m;  // UnknownHandle
      found.clear();
      world.overlap_query(centre, centre, kGroupAll, -1, found);
      for (const Body* body : found) {
        if (body->handle == bodies[i].handle) self_[i] = body;
      }
    }
    rebuild_neighbours();
  }

  // Penetrating contacts of body i, in handle order (as CollisionWorld::contacts gives them).
  void contacts(std::size_t i, std::vector<Contact>& out) {
    out.clear();
    const PlanarShape self = self_[i] ? planar_shape(*self_[i]) : PlanarShape();
    if (self.kind != PlanarShape::Kind::kCircle) {
      out = world_.contacts(handles_[i]);
      return;
    }
    if (max_drift_m_ > 0.5 * kNeighbourMargin_m) rebuild_neighbours();
    const Vec3 self_min(self.circle.centre_m.x() - self.circle.radius_m,
                        self.circle.centre_m.y() - self.circle.radius_m, self.circle.z_min_m);
    const Vec3 self_max(self.circle.centre_m.x() + self.circle.radius_m,
                        self.circle.centre_m.y() + self.circle.radius_m, self.circle.z_max_m);
    fallback_handles_.clear();
    for (std::size_t k = first_[i]; k < first_[i + 1]; ++k) {
      const Body& other = *neighbours_[k];
      const PlanarShape shape = planar_shape(other);
      std::optional<Penetration> found;
      if (shape.kind == PlanarShape::Kind::kCircle) {
        found = penetration(self.circle, shape.circle);
      } else if (shape.kind == PlanarShape::Kind::kRectangle) {
        found = penetration(self.circle, shape.rectangle);
      } else if (const btBroadphaseProxy* proxy = other.object->getBroadphaseHandle();
                 boxes_overlap(self_min, self_max, proxy->m_aabbMin, proxy->m_aabbMax)) {
        fallback_handles_.push_back(other.handle);
      }
      if (found) out.push_back(Contact{other.handle, found->normal, found->depth_m});
    }
    if (!fallback_handles_.empty()) add_bullet_contacts(handles_[i], out);
  }

  // Records that body i moved (it is the caller's job to move it in the world).
  void moved(std::size_t i, const Eigen::Vector2d& move) {
    drift_m_[i] += move;
    max_drift_m_ = std::max(max_drift_m_, drift_m_[i].cwiseAbs().maxCoeff());
  }

 private:
  // A neighbour list holds whatever the broadphase finds within the margin of a body's box;
  // until a body drifts half the margin, no pair can come into contact without being listed.
  void rebuild_neighbours() {
    neighbours_.clear();
    first_.assign(1, 0);
    for (std::size_t i = 0; i < self_.size(); ++i) {
      const PlanarShape self = self_[i] ? planar_shape(*self_[i]) : PlanarShape();
      if (self.kind == PlanarShape::Kind::kCircle) {
        const UprightCircle& circle = self.circle;
        const double reach_m = circle.radius_m + kNeighbourMargin_m;
        world_.overlap_query(
            Vec3(circle.centre_m.x() - reach_m, circle.centre_m.y() - reach_m, circle.z_min_m),
            Vec3(circle.centre_m.x() + reach_m, circle.centre_m.y() + reach_m, circle.z_max_m),
            contact_mask(self_[i]->group), self_[i]->handle, neighbours_);
      }
      first_.push_back(neighbours_.size());
    }
    std::fill(drift_m_.begin(), drift_m_.end(), Eigen::Vector2d::Zero());
    max_drift_m_ = 0.0;
  }

  // Bullet's contacts with the neighbours no closed form covers, merged in handle order.
  void add_bullet_contacts(int handle, std::vector<Contact>& out) {
    for (const Contact& contact : world_.contacts(handle)) {
      if (std::find(fallback_handles_.begin(), fallback_handles_.end(), contact.other_handle) !=
          fallback_handles_.end()) {
        out.push_back(contact);
      }
    }
    std::stable_sort(out.begin(), out.end(), [](const Contact& a, const Contact& b) {
      return a.other_handle < b.other_handle;
    });
  }

  CollisionWorld& world_;
  std::vector<int> handles_;             // per listed body
  std::vector<const Body*> self_;        // per listed body, null if the world lost it
  std::vector<const Body*> neighbours_;  // body i's are [first_[i], first_[i + 1])
  std::vector<std::size_t> first_;
  std::vector<Eigen::Vector2d> drift_m_;  // each body's displacement since the rebuild
  double max_drift_m_ = 0.0;              // the largest coordinate any of them reached
  std::vector<int> fallback_handles_;
};

}  // namespace

double resolve_penetrations(CollisionWorld& world, std::vector<MovableBody>& bodies,
                            const ContactSettings& settings) {
  std::unordered_map<int, size_t> index_of;
  for (size_t i = 0; i < bodies.size(); ++i) index_of.emplace(bodies[i].handle, i);
  ContactFinder finder(world, bodies);
  const auto translate = [&](size_t i, const Eigen::Vector2d& move) {
    bodies[i].pose.position_m.x() += move.x();
    bodies[i].pose.position_m.y() += move.y();
    world.set_pose(bodies[i].handle, bodies[i].pose);
    finder.moved(i, move);
  };
  std::vector<char> active(bodies.size(), 1);
  std::vector<char> next_active(bodies.size(), 0);
  std::vector<Contact> contacts;
  double deepest = 0.0;
  for (int pass = 0; pass < settings.max_passes; ++pass) {
    deepest = 0.0;
    std::fill(next_active.begin(), next_active.end(), 0);
    for (size_t i = 0; i < bodies.size(); ++i) {
      if (!active[i]) continue;
      Eigen::Vector2d move = Eigen::Vector2d::Zero();
      finder.contacts(i, contacts);
      for (const Contact& contact : contacts) {
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
          translate(other->second, other_move);
          next_active[other->second] = 1;
        }
      }
      if (!move.isZero()) {
        translate(i, move);
        next_active[i] = 1;
      }
    }
    if (deepest <= settings.tolerance_m) break;
    active.swap(next_active);
  }
  return deepest;
}

}  // namespace evc
