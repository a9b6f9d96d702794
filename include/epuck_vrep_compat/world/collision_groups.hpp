/// @file
/// Collision filter groups: every object in a CollisionWorld belongs to exactly one group.
///
/// Contacts: robots touch STATIC, DYNAMIC and other ROBOT objects, never the FLOOR (they stand on
/// it). Rays and the camera ignore this table: they see every group named in their mask.
#pragma once

namespace evc {

/// Filter groups, one bit each so masks can combine them.
enum CollisionGroup : int {
  kGroupStatic = 1,   ///< walls, fixed obstacles
  kGroupRobot = 2,    ///< robot bodies
  kGroupFloor = 4,    ///< the ground plane and things lying flat on it
  kGroupDynamic = 8,  ///< movable objects (treated as fixed by contact resolution)
  kGroupAll = 15,     ///< every group, as a ray or camera mask
};

/// True when @p group is exactly one of the four group bits.
bool is_single_group(int group);

/// The groups an object of @p group is allowed to be in contact with.
int contact_mask(int group);

}  // namespace evc
