#include "epuck_vrep_compat/world/collision_groups.hpp"

namespace evc {

bool is_single_group(int group) {
  return group == kGroupStatic || group == kGroupRobot || group == kGroupFloor ||
         group == kGroupDynamic;
}

int contact_mask(int group) {
  switch (group) {
    case kGroupRobot:
      return kGroupStatic | kGroupDynamic | kGroupRobot;
    case kGroupStatic:
      return kGroupRobot | kGroupDynamic;
    case kGroupFloor:
      return kGroupDynamic;
    case kGroupDynamic:
      return kGroupAll;
    default:
      return 0;
  }
}

}  // namespace evc
