/// @file
/// Pushes robot bodies out of whatever they penetrate, in the ground plane.
///
/// Robots are kinematic: nothing pushes back with forces, so contact is resolved by moving the
/// bodies. Each pass asks Bullet's narrowphase (CollisionWorld::contacts) for the penetrating
/// contacts of each body and moves the body along the contact normals projected on the ground
/// plane, by the depth of each contact not already covered by the move so far (two collinear
/// contacts, e.g. a wall built of two boxes, do not push twice; a corner pushes along both
/// walls). Two bodies of the same list share a contact half and half, pushed apart along the
/// line between their vertical axes (the list holds upright cylinders); everything else (walls,
/// other robots) does not move. Passes repeat, visiting only bodies that moved or touched
/// something, until no penetration deeper than the tolerance remains or the passes run out.
#pragma once

#include <vector>

#include "epuck_vrep_compat/collision_world.hpp"

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

/// Resolves penetrations of @p bodies, updating their poses here and in @p world.
/// Returns the deepest penetration found by the last pass, metres.
double resolve_penetrations(CollisionWorld& world, std::vector<MovableBody>& bodies,
                            const ContactSettings& settings = ContactSettings());

}  // namespace evc
