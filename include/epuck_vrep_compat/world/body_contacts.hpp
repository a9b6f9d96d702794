/// @file
/// Pushes robot bodies out of whatever they penetrate, in the ground plane.
///
/// Robots are kinematic: nothing pushes back with forces, so contact is resolved by moving the
/// bodies. Each pass visits the bodies in list order, finds each one's penetrating contacts
/// and moves it along the contact normals projected on the ground plane, by the depth of each
/// contact not already covered by the move so far (two collinear contacts, e.g. a wall built of
/// two boxes, do not push twice; a corner pushes along both walls). Two bodies of the list share
/// a contact half and half, pushed apart along the line between their vertical axes (the list
/// holds upright cylinders); everything else (walls, other objects) does not move. Passes
/// repeat, visiting only bodies that moved, until no penetration deeper than the tolerance
/// remains or the passes run out. Contacts obey the collision groups (contact_mask): a robot
/// never touches the floor.
///
/// Narrowphase. A listed upright cylinder (axis along world z) meets upright cylinders and
/// upright boxes (local z along world z, any yaw) through the closed forms of
/// planar_contacts.hpp, exact to rounding: circle against circle, or circle against rectangle,
/// in the ground plane, whenever their heights overlap; a robot whose centre is inside a box
/// leaves through the nearest face. Anything else (spheres, tilted shapes, a listed body that
/// is not an upright cylinder) goes through Bullet's GJK/EPA narrowphase
/// (CollisionWorld::contacts), whose normals may tilt out of the plane; a (nearly) vertical one
/// counts towards the depth but moves nothing. Contacts are taken in handle order either way,
/// so a run is reproduced bit for bit.
///
/// Broadphase. Each upright cylinder keeps a list of what the Bullet broadphase finds within a
/// margin of it, built for all bodies in one batch and rebuilt only once some body has moved
/// half the margin since (until then no unlisted pair can have closed the gap). The world
/// learns the moved poses at each rebuild, before each Bullet query and at the end. A
/// ContactCache carries the lists from one call to the next.
#pragma once

#include <memory>
#include <vector>

#include "epuck_vrep_compat/world/collision_world.hpp"

namespace evc {

/// A body to keep out of penetration; its pose is read and updated (x and y only).
struct MovableBody {
  int handle;
  Pose pose;
};

/// Limits of the resolution.
struct ContactSettings {
  int max_passes = 16;        ///< passes over the bodies at most
  double tolerance_m = 1e-4;  ///< a pass that finds no deeper penetration ends the resolution
  double slop_m = 1e-6;       ///< extra push, so a resolved contact does not reappear by rounding
};

/// The neighbour lists of one resolve_penetrations call, handed to the next. They are taken
/// over while they still hold: the same bodies (handles, in order) as upright cylinders of the
/// same radius and heights, nothing else changed the world since (CollisionWorld::revision),
/// and no body has drifted half the margin since they were built (the same rule as within a
/// call). Otherwise they are rebuilt, so a cache changes how soon the answer comes, never the
/// answer. A stepper that moves the same robots every step keeps one.
class ContactCache {
 public:
  ContactCache();
  ~ContactCache();
  ContactCache(ContactCache&&) noexcept;
  ContactCache& operator=(ContactCache&&) noexcept;
  /// Forgets the lists: the next call rebuilds them.
  void clear();
  /// Uses @p other's working lists (which hold nothing from one call to the next) instead of
  /// its own, so that many small worlds resolved one after the other keep one copy of them in
  /// the cache. Caches that share must never be used at the same time.
  void share_scratch(const ContactCache& other);

  struct State;    // defined where it is used
  struct Scratch;  // likewise

 private:
  friend double resolve_penetrations(CollisionWorld&, std::vector<MovableBody>&,
                                     const ContactSettings&, ContactCache*,
                                     std::vector<char>*);
  std::unique_ptr<State> state_;
};

/// Resolves penetrations of @p bodies: places each at its given pose in @p world first, and
/// leaves the resolved poses in both. Throws UnknownHandle for a body the world lacks.
/// Returns the deepest penetration found by the last pass, metres. With @p cache, the
/// neighbour lists of the previous call with the same cache are reused when they still hold.
/// With @p touched, entry i is set to 1 when body i was in a penetrating contact (with anything,
/// listed or not) in any pass, else 0: what the bodies bumped into during this call.
double resolve_penetrations(CollisionWorld& world, std::vector<MovableBody>& bodies,
                            const ContactSettings& settings = ContactSettings(),
                            ContactCache* cache = nullptr, std::vector<char>* touched = nullptr);

}  // namespace evc
