#include "epuck_vrep_compat/world/body_contacts.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <unordered_map>

#include "body.hpp"
#include "epuck_vrep_compat/world/planar_contacts.hpp"

namespace evc {
namespace {

// A shape counts as upright when its local z axis leans less than this (radians) off world z:
// the tilt moves a 5 cm tall wall's faces by 50 pm at most.
constexpr double kUprightTolerance = 1e-9;
// Neighbour lists hold what lies within this gap of a body, so they stay valid until some
// body has moved half of it; larger means fewer rebuilds and longer lists. Robots jammed
// against a wall can be pushed several centimetres within one resolution, each time
// rebuilding every list: at 1000 robots a 3 cm margin rebuilt them about 7 times a step.
constexpr double kNeighbourMargin_m = 0.06;

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

// Whether a circle can come into contact with a body after planar moves of @p margin_m in
// all: exact for prisms, through the bounding sphere for anything else.
bool within_reach(const UprightCircle& circle, const PlanarShape& shape, const Body& body,
                  double margin_m) {
  switch (shape.kind) {
    case PlanarShape::Kind::kCircle:
      return circle.z_min_m < shape.circle.z_max_m && shape.circle.z_min_m < circle.z_max_m &&
             planar_separation(circle, shape.circle).distance_m < margin_m;
    case PlanarShape::Kind::kRectangle:
      return circle.z_min_m < shape.rectangle.z_max_m &&
             shape.rectangle.z_min_m < circle.z_max_m &&
             planar_separation(circle, shape.rectangle).distance_m < margin_m;
    case PlanarShape::Kind::kOther:
      break;
  }
  const BoundingSphere sphere = CollisionWorld::bounding_sphere(body);
  const UprightCircle bound{sphere.centre_m.head<2>(), sphere.radius_m,
                            sphere.centre_m.z() - sphere.radius_m,
                            sphere.centre_m.z() + sphere.radius_m};
  return circle.z_min_m <= bound.z_max_m && bound.z_min_m <= circle.z_max_m &&
         planar_separation(circle, bound).distance_m <= margin_m;
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

// A contact of a listed body, and the index of the other body if it is listed too (else -1).
struct Touch {
  Contact contact;
  long other;
};

struct Neighbour {
  const Body* body;
  long listed;  // index of a listed body, whose shape moves with it; -1 if it stays put
};

// A body of a small world at a rebuild of the neighbour lists (ContactFinder::describe_all).
struct Described {
  PlanarShape shape;
  long listed;            // as Neighbour's
  Eigen::Vector2d low_m;  // a box in the plane that holds the body
  Eigen::Vector2d high_m;
};

}  // namespace

// The working lists of one call (ContactFinder).
struct ContactCache::Scratch {
  std::vector<PlanarShape> shape;                // per listed body, centre as at the start
  std::vector<char> dirty;                       // moved since the world last learnt its pose
  std::vector<std::size_t> moved;                // the dirty bodies, in the order they moved
  std::vector<const Body*> found;                // broadphase answers
  std::vector<std::size_t> found_first;
  std::vector<BoxQuery> queries;                 // the rebuild's, one per cylinder
  std::vector<std::size_t> circles;              // the cylinders' indices, ascending
  std::vector<Described> described;              // a small world's bodies, in handle order
  std::vector<char> active, next_active;         // bodies to visit in this pass, the next
  std::vector<Touch> touches;                    // one body's contacts
};

// The neighbour lists and what they were built for; kept in a ContactCache between calls.
struct ContactCache::State {
  bool valid = false;                              // a call completed with these lists
  std::uint64_t revision = 0;                      // the world's, as that call left it
  std::vector<int> handles;                        // per listed body
  std::unordered_map<int, std::size_t> index_of;   // handle -> listed body (lookups only)
  std::vector<const Body*> self;                   // per listed body
  std::vector<UprightCircle> circles;              // per listed body, at the rebuild
  std::vector<Eigen::Vector2d> anchor_m;           // per listed body: where, at the rebuild
  std::vector<Neighbour> neighbours;               // body i's: [first[i], first[i + 1])
  std::vector<std::size_t> first;
  // Scratch of one call, kept so that a stepper calling every step allocates nothing (and
  // shared between caches by share_scratch).
  std::shared_ptr<Scratch> scratch = std::make_shared<Scratch>();
};

ContactCache::ContactCache() : state_(std::make_unique<State>()) {}
ContactCache::~ContactCache() = default;
ContactCache::ContactCache(ContactCache&&) noexcept = default;
ContactCache& ContactCache::operator=(ContactCache&&) noexcept = default;
void ContactCache::clear() { state_->valid = false; }
void ContactCache::share_scratch(const ContactCache& other) {
  state_->scratch = other.state_->scratch;
}

namespace {

// Finds the contacts of the listed bodies and moves them. Poses live in the MovableBody list
// while passes run; the world learns them before anything reads it (a rebuild of the
// neighbour lists, a Bullet query) and at the end. The neighbour lists of the last call are
// taken over when they still hold (see ContactCache), else rebuilt.
class ContactFinder {
 public:
  using State = ContactCache::State;

  ContactFinder(CollisionWorld& world, std::vector<MovableBody>& bodies, State& state)
      : world_(world), bodies_(bodies), state_(state), shape_(state.scratch->shape),
        dirty_(state.scratch->dirty), moved_(state.scratch->moved), found_(state.scratch->found),
        found_first_(state.scratch->found_first), queries_(state.scratch->queries),
        circles_(state.scratch->circles), described_(state.scratch->described) {
    shape_.assign(bodies.size(), PlanarShape());
    dirty_.assign(bodies.size(), 0);
    moved_.clear();
    bool same_world = state_.valid && state_.revision == world.revision() &&
                      state_.handles.size() == bodies.size();
    for (std::size_t i = 0; same_world && i < bodies.size(); ++i) {
      same_world = state_.handles[i] == bodies[i].handle;
    }
    state_.valid = false;  // until this call completes
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      // The same world still holds the bodies of the lists; else UnknownHandle for a body the
      // world lacks.
      if (same_world) {
        world.set_pose(*state_.self[i], bodies[i].pose);
      } else {
        world.set_pose(bodies[i].handle, bodies[i].pose);
      }
    }
    if (!same_world) {
      state_.handles.clear();
      state_.index_of.clear();
      state_.self.clear();
      for (std::size_t i = 0; i < bodies.size(); ++i) {
        state_.handles.push_back(bodies[i].handle);
        state_.index_of.emplace(bodies[i].handle, i);
        state_.self.push_back(&world.body(bodies[i].handle));
      }
    }
    bool reusable = same_world && state_.circles.size() == bodies.size();
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      shape_[i] = planar_shape(*state_.self[i]);
      reusable = reusable && shape_[i].kind == PlanarShape::Kind::kCircle &&
                 same_circle(shape_[i].circle, state_.circles[i]);
    }
    if (!reusable) {
      rebuild_neighbours();
      return;
    }
    for (std::size_t i = 0; i < bodies.size(); ++i) note_drift(i);
  }

  // After the last move: the lists hold for the next call until something changes the world.
  void finish() {
    sync();
    state_.revision = world_.revision();
    state_.valid = true;
  }

  // Penetrating contacts of body i, in handle order (as CollisionWorld::contacts gives them).
  void contacts(std::size_t i, std::vector<Touch>& out) {
    out.clear();
    if (shape_[i].kind != PlanarShape::Kind::kCircle) {
      add_bullet_contacts(i, false, out);
      return;
    }
    if (max_drift_squared_ > 0.25 * kNeighbourMargin_m * kNeighbourMargin_m) {
      rebuild_neighbours();
    }
    const UprightCircle self = shape_now(i).circle;
    bool needs_bullet = false;
    for (std::size_t k = state_.first[i]; k < state_.first[i + 1]; ++k) {
      const Neighbour& neighbour = state_.neighbours[k];
      const bool listed = neighbour.listed >= 0;
      PlanarShape fixed;  // a body that stays put: where it is
      if (!listed) fixed = planar_shape(*neighbour.body);
      const PlanarShape& shape = listed ? shape_[neighbour.listed] : fixed;
      std::optional<Penetration> found;
      if (shape.kind == PlanarShape::Kind::kCircle) {
        UprightCircle other = shape.circle;
        if (listed) other.centre_m = position(neighbour.listed);
        found = penetration(self, other);
      } else if (shape.kind == PlanarShape::Kind::kRectangle) {
        UprightRectangle other = shape.rectangle;
        if (listed) other.centre_m = position(neighbour.listed);
        found = penetration(self, other);
      } else {
        needs_bullet = true;
      }
      if (!found) continue;
      out.push_back(Touch{Contact{neighbour.body->handle, found->normal, found->depth_m},
                          neighbour.listed});
    }
    if (needs_bullet) add_bullet_contacts(i, true, out);
  }

  // Moves body i in the plane.
  void translate(std::size_t i, const Eigen::Vector2d& move) {
    bodies_[i].pose.position_m.x() += move.x();
    bodies_[i].pose.position_m.y() += move.y();
    note_drift(i);
    if (!dirty_[i]) {
      dirty_[i] = 1;
      moved_.push_back(i);
    }
  }

  // Hands the moved bodies' poses to the world.
  void sync() {
    for (const std::size_t i : moved_) {
      world_.set_pose(*state_.self[i], bodies_[i].pose);
      dirty_[i] = 0;
    }
    moved_.clear();
  }

 private:
  static bool same_circle(const UprightCircle& a, const UprightCircle& b) {
    return a.radius_m == b.radius_m && a.z_min_m == b.z_min_m && a.z_max_m == b.z_max_m;
  }

  Eigen::Vector2d position(std::size_t i) const { return bodies_[i].pose.position_m.head<2>(); }

  // Keeps the longest displacement of a body since the lists were built.
  void note_drift(std::size_t i) {
    max_drift_squared_ =
        std::max(max_drift_squared_, (position(i) - state_.anchor_m[i]).squaredNorm());
  }

  // The shape of listed body i where it is now.
  PlanarShape shape_now(std::size_t i) const {
    PlanarShape shape = shape_[i];
    shape.circle.centre_m = shape.rectangle.centre_m = position(i);
    return shape;
  }

  long listed_index(int handle) const {
    const auto it = state_.index_of.find(handle);
    return it == state_.index_of.end() ? -1 : static_cast<long>(it->second);
  }

  // Lists for each upright cylinder, in handle order, what could touch it before some body
  // has drifted half the margin (two bodies then close a gap of one margin at most): the
  // exact gap decides, among what the broadphase finds in the margin of each cylinder's box or,
  // in a small world, among every body whose box comes that near (without the broadphase,
  // whose boxes then need no update).
  void rebuild_neighbours() {
    sync();
    const std::vector<const Body*>& everything = world_.bodies_in_handle_order();
    const bool small = everything.size() <= kSmallWorld;
    if (small) {
      describe_all(everything);
    } else {
      query_broadphase();
    }
    std::vector<Neighbour>& neighbours = state_.neighbours;
    neighbours.clear();
    state_.first.assign(bodies_.size() + 1, 0);
    for (std::size_t q = 0, i = 0; i < bodies_.size(); ++i) {
      if (shape_[i].kind != PlanarShape::Kind::kCircle) {
        state_.first[i + 1] = neighbours.size();
        continue;
      }
      const UprightCircle self = shape_now(i).circle;
      const int mask = contact_mask(state_.self[i]->group);
      if (small) {
        const double reach_m = self.radius_m + kNeighbourMargin_m + 1e-9;
        for (std::size_t k = 0; k < everything.size(); ++k) {
          const Body& other = *everything[k];
          const Described& seen = described_[k];
          if (&other == state_.self[i] || (other.group & mask) == 0 ||
              seen.low_m.x() > self.centre_m.x() + reach_m ||
              seen.high_m.x() < self.centre_m.x() - reach_m ||
              seen.low_m.y() > self.centre_m.y() + reach_m ||
              seen.high_m.y() < self.centre_m.y() - reach_m) {
            continue;
          }
          if (within_reach(self, seen.shape, other, kNeighbourMargin_m)) {
            neighbours.push_back(Neighbour{&other, seen.listed});
          }
        }
      } else {
        for (std::size_t k = found_first_[q]; k < found_first_[q + 1]; ++k) {
          const Body& other = *found_[k];
          if ((other.group & mask) == 0) continue;
          const long listed = listed_index(other.handle);
          const PlanarShape shape = listed >= 0 ? shape_now(listed) : planar_shape(other);
          if (within_reach(self, shape, other, kNeighbourMargin_m)) {
            neighbours.push_back(Neighbour{&other, listed});
          }
        }
        ++q;
      }
      state_.first[i + 1] = neighbours.size();
    }
    state_.circles.resize(bodies_.size());
    state_.anchor_m.resize(bodies_.size());
    for (std::size_t i = 0; i < bodies_.size(); ++i) {
      state_.circles[i] = shape_[i].circle;
      state_.anchor_m[i] = position(i);
    }
    max_drift_squared_ = 0.0;
  }

  // The broadphase's answers for each upright cylinder's box widened by the margin: the
  // cylinders' indices in circles_, what each box finds in found_ from found_first_.
  void query_broadphase() {
    queries_.clear();
    circles_.clear();
    int mask = 0;
    for (std::size_t i = 0; i < bodies_.size(); ++i) {
      if (shape_[i].kind != PlanarShape::Kind::kCircle) continue;
      const UprightCircle circle = shape_now(i).circle;
      const double reach_m = circle.radius_m + kNeighbourMargin_m;
      queries_.push_back(BoxQuery{
          Vec3(circle.centre_m.x() - reach_m, circle.centre_m.y() - reach_m, circle.z_min_m),
          Vec3(circle.centre_m.x() + reach_m, circle.centre_m.y() + reach_m, circle.z_max_m),
          state_.self[i]->handle});
      circles_.push_back(i);
      mask |= contact_mask(state_.self[i]->group);
    }
    overlap_query_batch(world_, queries_, mask, found_first_, found_);
  }

  // Each of a small world's bodies (@p everything) where it is now: its shape, the listed body
  // it is (-1 for none) and a box in the plane that holds it (a bounding square for a shape
  // without closed form).
  void describe_all(const std::vector<const Body*>& everything) {
    described_.resize(everything.size());
    for (std::size_t k = 0; k < everything.size(); ++k) {
      Described& seen = described_[k];
      seen.listed = listed_index(everything[k]->handle);
      seen.shape = seen.listed >= 0 ? shape_now(seen.listed) : planar_shape(*everything[k]);
      Eigen::Vector2d centre_m = Eigen::Vector2d::Zero(), half_m = Eigen::Vector2d::Zero();
      switch (seen.shape.kind) {
        case PlanarShape::Kind::kCircle:
          centre_m = seen.shape.circle.centre_m;
          half_m.setConstant(seen.shape.circle.radius_m);
          break;
        case PlanarShape::Kind::kRectangle: {
          const UprightRectangle& box = seen.shape.rectangle;
          centre_m = box.centre_m;
          half_m = box.axis_x.cwiseAbs() * box.half_extents_m.x() +
                   box.axis_y.cwiseAbs() * box.half_extents_m.y();
          break;
        }
        case PlanarShape::Kind::kOther: {
          const BoundingSphere sphere = CollisionWorld::bounding_sphere(*everything[k]);
          centre_m = sphere.centre_m.head<2>();
          half_m.setConstant(sphere.radius_m);
          break;
        }
      }
      // Widened a little: rounding must never drop a body that within_reach would keep.
      half_m = half_m * (1.0 + 1e-9) + Eigen::Vector2d::Constant(1e-9);
      seen.low_m = centre_m - half_m;
      seen.high_m = centre_m + half_m;
    }
  }

  // Bullet's contacts of body i; with @p only_other_shapes, only those with bodies that have no
  // closed form (the others are in @p out already), merged in handle order.
  void add_bullet_contacts(std::size_t i, bool only_other_shapes, std::vector<Touch>& out) {
    sync();
    for (const Contact& contact : world_.contacts(bodies_[i].handle)) {
      const long listed = listed_index(contact.other_handle);
      if (only_other_shapes && has_closed_form(i, contact.other_handle)) continue;
      Touch touch{contact, listed};
      if (listed >= 0) touch.contact.normal = centre_line(i, listed, contact.normal);
      out.push_back(touch);
    }
    std::stable_sort(out.begin(), out.end(), [](const Touch& a, const Touch& b) {
      return a.contact.other_handle < b.contact.other_handle;
    });
  }

  // Two listed bodies (upright cylinders) part along the line between their axes, as the
  // closed form has them do. Bullet's EPA normal is off by ~3e-4 rad in deep contacts, enough
  // to let two robots pushing nose to nose creep sideways past each other.
  Vec3 centre_line(std::size_t i, std::size_t other, const Vec3& fallback) const {
    const Eigen::Vector2d line = position(i) - position(other);
    const double length = line.norm();
    return length > 1e-9 ? Vec3(line.x() / length, line.y() / length, 0.0) : fallback;
  }

  // Whether body i's contact with @p handle came from a closed form.
  bool has_closed_form(std::size_t i, int handle) const {
    for (std::size_t k = state_.first[i]; k < state_.first[i + 1]; ++k) {
      const Neighbour& neighbour = state_.neighbours[k];
      if (neighbour.body->handle != handle) continue;
      const PlanarShape::Kind kind = neighbour.listed >= 0 ? shape_[neighbour.listed].kind
                                                           : planar_shape(*neighbour.body).kind;
      return kind != PlanarShape::Kind::kOther;
    }
    return false;
  }

  CollisionWorld& world_;
  std::vector<MovableBody>& bodies_;
  State& state_;                          // the lists, this call's or kept from the last
  double max_drift_squared_ = 0.0;        // longest displacement since the rebuild, squared
  // The state's scratch (see ContactCache::Scratch).
  std::vector<PlanarShape>& shape_;
  std::vector<char>& dirty_;
  std::vector<std::size_t>& moved_;
  std::vector<const Body*>& found_;
  std::vector<std::size_t>& found_first_;
  std::vector<BoxQuery>& queries_;
  std::vector<std::size_t>& circles_;
  std::vector<Described>& described_;
};

}  // namespace

double resolve_penetrations(CollisionWorld& world, std::vector<MovableBody>& bodies,
                            const ContactSettings& settings, ContactCache* cache,
                            std::vector<char>* touched) {
  if (touched != nullptr) touched->assign(bodies.size(), 0);
  std::optional<ContactCache::State> this_call;  // lists for this call alone, without a cache
  if (cache == nullptr) this_call.emplace();
  ContactCache::State& state = cache != nullptr ? *cache->state_ : *this_call;
  ContactFinder finder(world, bodies, state);
  std::vector<char>& active = state.scratch->active;
  std::vector<char>& next_active = state.scratch->next_active;
  std::vector<Touch>& touches = state.scratch->touches;
  active.assign(bodies.size(), 1);
  next_active.assign(bodies.size(), 0);
  double deepest = 0.0;
  for (int pass = 0; pass < settings.max_passes; ++pass) {
    deepest = 0.0;
    std::fill(next_active.begin(), next_active.end(), 0);
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      if (!active[i]) continue;
      Eigen::Vector2d move = Eigen::Vector2d::Zero();
      finder.contacts(i, touches);
      if (touched != nullptr && !touches.empty()) (*touched)[i] = 1;
      for (const Touch& touch : touches) {
        if (touched != nullptr && touch.other >= 0) (*touched)[touch.other] = 1;
        const Contact& contact = touch.contact;
        deepest = std::max(deepest, contact.depth_m);
        const bool shared = touch.other >= 0;
        const double share = shared ? 0.5 : 1.0;
        if (!cover(contact.normal, share * contact.depth_m + settings.slop_m, move)) continue;
        if (shared) {
          Eigen::Vector2d other_move = Eigen::Vector2d::Zero();
          cover(-contact.normal, share * contact.depth_m + settings.slop_m, other_move);
          finder.translate(touch.other, other_move);
          next_active[touch.other] = 1;
        }
      }
      if (!move.isZero()) {
        finder.translate(i, move);
        next_active[i] = 1;
      }
    }
    if (deepest <= settings.tolerance_m) break;
    active.swap(next_active);
  }
  finder.finish();
  return deepest;
}

}  // namespace evc
