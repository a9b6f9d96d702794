#include "epuck_vrep_compat/world/collision_world.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <BulletCollision/BroadphaseCollision/btDbvtBroadphase.h>
#include <btBulletCollisionCommon.h>

#include "body.hpp"
#include "bullet_conversions.hpp"
#include "pose_checks.hpp"

namespace evc {
namespace {

void check_size(double value, const char* name) {
  if (!(value > 0.0 && value <= kWorldLimit_m)) {
    throw std::invalid_argument(std::string(name) + " must be in (0, 1e6] m");
  }
}

void check_rgb(const Vec3& rgb) {
  if (!rgb.allFinite() || rgb.minCoeff() < 0.0 || rgb.maxCoeff() > 1.0) {
    throw std::invalid_argument("rgb must hold three values in [0, 1]");
  }
}

std::unique_ptr<Body> new_body(int handle, int group, const Vec3& rgb) {
  if (handle < 0) throw std::invalid_argument("handle must be >= 0 (-1 means 'none')");
  if (!is_single_group(group)) {
    throw std::invalid_argument("group must be one of GROUP_STATIC, GROUP_ROBOT, GROUP_FLOOR, "
                                "GROUP_DYNAMIC");
  }
  check_rgb(rgb);
  auto body = std::make_unique<Body>();
  body->handle = handle;
  body->group = group;
  body->rgb = rgb;
  return body;
}

// Reports penetrating contacts of one object, with normals turned to point towards it.
class ContactCollector : public btCollisionWorld::ContactResultCallback {
 public:
  ContactCollector(const btCollisionObject* self, int group, std::vector<Contact>& out)
      : self_(self), out_(out) {
    m_collisionFilterGroup = group;
    m_collisionFilterMask = contact_mask(group);
  }

  btScalar addSingleResult(btManifoldPoint& point, const btCollisionObjectWrapper* wrapper0,
                           int, int, const btCollisionObjectWrapper* wrapper1, int,
                           int) override {
    if (point.getDistance() >= 0.0) return 0;
    // Bullet's normal points from object B towards object A.
    const bool self_is_a = wrapper0->getCollisionObject() == self_;
    const btCollisionObject* other =
        self_is_a ? wrapper1->getCollisionObject() : wrapper0->getCollisionObject();
    const btVector3 normal = self_is_a ? point.m_normalWorldOnB : -point.m_normalWorldOnB;
    out_.push_back(Contact{static_cast<const Body*>(other->getUserPointer())->handle,
                           to_eigen(normal), -point.getDistance()});
    return 0;
  }

 private:
  const btCollisionObject* self_;
  std::vector<Contact>& out_;
};

// Bullet's default configuration preallocates pools of 4096 contact manifolds and 4096
// collision algorithms, about 7 MB a world, touched page by page as it builds their free lists.
// Here contacts are only queried one object at a time (contactTest), which holds a couple of
// each for the length of the query, and Bullet takes more from the heap when a pool runs dry:
// small pools change no result and let thousands of small worlds (BatchedWorlds) fit in memory.
btDefaultCollisionConstructionInfo small_pools() {
  btDefaultCollisionConstructionInfo info;
  info.m_defaultMaxPersistentManifoldPoolSize = 8;
  info.m_defaultMaxCollisionAlgorithmPoolSize = 8;
  return info;
}

}  // namespace

CollisionWorld::CollisionWorld()
    : configuration_(std::make_unique<btDefaultCollisionConfiguration>(small_pools())),
      dispatcher_(std::make_unique<btCollisionDispatcher>(configuration_.get())),
      // Nothing here consumes broadphase pairs (contacts are queried per object), so a null
      // pair cache keeps Bullet from storing pairs that nobody would ever clean up.
      pair_cache_(std::make_unique<btNullPairCache>()),
      broadphase_(std::make_unique<btDbvtBroadphase>(pair_cache_.get())),
      world_(std::make_unique<btCollisionWorld>(dispatcher_.get(), broadphase_.get(),
                                                configuration_.get())) {
  // Bullet would look for the pairs a moved box now overlaps, on every move, only to hand them
  // to the null pair cache: deferred, they are never looked for (maintain_broadphase only
  // rebalances the tree).
  broadphase_->m_deferedcollide = true;
}

CollisionWorld::~CollisionWorld() {
  // The Bullet world reads its objects while it is destroyed, so detach them first.
  for (auto& entry : bodies_) world_->removeCollisionObject(entry.second->object.get());
}

void CollisionWorld::add_box(int handle, const Vec3& half_extents_m, const Pose& pose,
                             const Vec3& rgb, int group) {
  for (int axis = 0; axis < 3; ++axis) check_size(half_extents_m[axis], "half_extents");
  auto body = new_body(handle, group, rgb);
  body->primitive.kind = Primitive::Kind::kBox;
  body->primitive.half_extents = to_bt(half_extents_m);
  body->shape = std::make_unique<btBoxShape>(to_bt(half_extents_m));
  add_body(std::move(body), pose);
}

void CollisionWorld::add_cylinder(int handle, double radius_m, double height_m, const Pose& pose,
                                  const Vec3& rgb, int group) {
  check_size(radius_m, "radius");
  check_size(height_m, "height");
  auto body = new_body(handle, group, rgb);
  body->primitive.kind = Primitive::Kind::kCylinder;
  body->primitive.radius_m = radius_m;
  body->primitive.half_height_m = 0.5 * height_m;
  body->shape =
      std::make_unique<btCylinderShapeZ>(btVector3(radius_m, radius_m, 0.5 * height_m));
  add_body(std::move(body), pose);
}

void CollisionWorld::add_sphere(int handle, double radius_m, const Pose& pose, const Vec3& rgb,
                                int group) {
  check_size(radius_m, "radius");
  auto body = new_body(handle, group, rgb);
  body->primitive.kind = Primitive::Kind::kSphere;
  body->primitive.radius_m = radius_m;
  body->shape = std::make_unique<btSphereShape>(radius_m);
  add_body(std::move(body), pose);
}

void CollisionWorld::add_body(std::unique_ptr<Body> body, const Pose& pose) {
  const Pose valid_pose = checked_pose(pose);
  if (bodies_.count(body->handle) != 0) {
    throw std::invalid_argument("handle " + std::to_string(body->handle) + " is already used");
  }
  body->object = std::make_unique<btCollisionObject>();
  body->object->setCollisionShape(body->shape.get());
  body->object->setWorldTransform(to_bt(valid_pose));
  body->object->setUserPointer(body.get());
  world_->addCollisionObject(body->object.get(), body->group, contact_mask(body->group));
  tree_changed_ = true;
  const auto at = std::lower_bound(ordered_.begin(), ordered_.end(), body->handle,
                                   [](const Body* a, int handle) { return a->handle < handle; });
  ordered_.insert(at, body.get());
  bodies_.emplace(body->handle, std::move(body));
  ++revision_;
}

Body& CollisionWorld::find(int handle) const {
  const auto it = bodies_.find(handle);
  if (it == bodies_.end()) throw UnknownHandle("no object with handle " + std::to_string(handle));
  return *it->second;
}

void CollisionWorld::set_pose(int handle, const Pose& pose) { set_pose(find(handle), pose); }

void CollisionWorld::set_pose(const Body& body, const Pose& pose) {
  Body& moved = const_cast<Body&>(body);  // one of bodies_, which the world owns and changes
  // Written in place rather than through setWorldTransform, whose update count (at the far
  // end of Bullet's object, one more cache line a move) nothing here reads: revision_ counts.
  moved.object->getWorldTransform() = to_bt(checked_pose(pose));
  mark_moved(moved);
  ++revision_;
}

void CollisionWorld::mark_moved(Body& body) {
  if (body.stale) return;
  body.stale = true;
  stale_.push_back(&body);
  any_stale_.store(true, std::memory_order_relaxed);
}

void CollisionWorld::refresh_broadphase() const {
  if (!any_stale_.load(std::memory_order_acquire)) return;
  const std::lock_guard<std::mutex> lock(refresh_mutex_);
  if (!any_stale_.load(std::memory_order_relaxed)) return;  // another thread did it
  for (Body* body : stale_) {
    world_->updateSingleAabb(body->object.get());
    body->stale = false;
  }
  stale_.clear();
  tree_changed_ = true;
  any_stale_.store(false, std::memory_order_release);
}

void CollisionWorld::set_poses(const std::vector<int>& handles, const std::vector<Pose>& poses) {
  if (handles.size() != poses.size()) {
    throw std::invalid_argument("handles and poses must have the same length");
  }
  std::vector<Body*> bodies;
  std::vector<Pose> valid_poses;
  bodies.reserve(handles.size());
  valid_poses.reserve(poses.size());
  for (std::size_t i = 0; i < handles.size(); ++i) {
    bodies.push_back(&find(handles[i]));
    valid_poses.push_back(checked_pose_at(poses, i, "poses"));
  }
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    bodies[i]->object->setWorldTransform(to_bt(valid_poses[i]));
    mark_moved(*bodies[i]);
  }
  ++revision_;
}

Pose CollisionWorld::get_pose(int handle) const {
  return to_pose(find(handle).object->getWorldTransform());
}

void CollisionWorld::remove(int handle) {
  Body& body = find(handle);
  if (body.stale) stale_.erase(std::find(stale_.begin(), stale_.end(), &body));
  if (stale_.empty()) any_stale_.store(false, std::memory_order_relaxed);
  world_->removeCollisionObject(body.object.get());
  tree_changed_ = true;
  ordered_.erase(std::find(ordered_.begin(), ordered_.end(), &body));
  bodies_.erase(handle);
  ++revision_;
}

bool CollisionWorld::has(int handle) const { return bodies_.count(handle) != 0; }

const Body& CollisionWorld::body(int handle) const { return find(handle); }

std::vector<int> CollisionWorld::handles() const {
  std::vector<int> out;
  out.reserve(ordered_.size());
  for (const Body* body : ordered_) out.push_back(body->handle);
  return out;
}

void CollisionWorld::set_color(int handle, const Vec3& rgb) {
  Body& body = find(handle);
  check_rgb(rgb);
  body.rgb = rgb;
}

void CollisionWorld::set_background(const Vec3& rgb) {
  check_rgb(rgb);
  background_rgb_ = rgb;
}

std::vector<Contact> CollisionWorld::contacts(int handle) {
  const Body& body = find(handle);
  std::vector<Contact> out;
  refresh_broadphase();
  ContactCollector collector(body.object.get(), body.group, out);
  world_->contactTest(body.object.get(), collector);
  // Bullet reports in broadphase-tree order, which depends on the history of moves; handle
  // order makes a replay after a reset resolve contacts bit for bit as the first run did.
  std::stable_sort(out.begin(), out.end(), [](const Contact& a, const Contact& b) {
    return a.other_handle < b.other_handle;
  });
  return out;
}

void CollisionWorld::maintain_broadphase() {
  // Boxes still stale stay so: a step that asked the broadphase nothing leaves it as it was.
  if (!tree_changed_) return;
  // What calculateOverlappingPairs would do but the pairs: one incremental pass over each tree.
  for (btDbvt& tree : broadphase_->m_sets) tree.optimizeIncremental(1);
  tree_changed_ = false;
}

}  // namespace evc
