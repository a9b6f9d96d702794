/// @file
/// The e-puck's infrared proximity sensor as V-REP models it: a cone, read as the distance from
/// the sensor origin to the closest point of anything inside the cone.
///
/// Frames and units: the mount is given in the robot body frame (x forward, y left, z up, z
/// measured from the ground), metres and radians; the sensor frame has x along the cone axis,
/// y left, z up, reached from the body frame by yaw about z, then pitch about the new y
/// (positive pitch tilts the axis down, REP 103).
///
/// Equation: with h = half_angle_rad,
///
///     r = min { |p - s| : p on an obstacle, angle(p - s, axis) <= h, |p - s| <= max_range_m }
///
/// and "nothing detected" when the set is empty. The minimum is taken over sampled rays: the
/// axis, plus `rings` rings at angles h k / rings (k = 1..rings), each with `azimuths` rays at
/// azimuth 2π j / azimuths measured from the sensor's +y axis about x. Azimuths 0 and π lie in
/// the sensor's horizontal (x-y) plane.
///
/// Why sampling reproduces the analytic reading within 1 mm at r <= 5 cm (defaults h = 15°,
/// rings = 2, azimuths = 16; ring spacing Δ = h / rings = 7.5°; ray hits are exact, see
/// collision_world.hpp, so the only error is where the rays fall):
///  - The closest point of a surface lies either at the foot of its normal, when that is inside
///    the cone, or on the cone's edge, in the plane that holds the axis and the normal. For a
///    vertical wall or a vertical cylinder seen by a level sensor that plane is the horizontal
///    one, which holds the axis and the edge rays at azimuths 0 and π: a normal outside the cone
///    (reading d / cos(θ - h), θ the normal's angle to the axis) and a normal along the axis are
///    sampled exactly.
///  - A normal inside the cone, in that plane, is at most Δ/2 from a sampled ray, so a plane
///    reads at most r (1 / cos(Δ/2) - 1) = 0.0021 r too far: 0.11 mm at 5 cm (measured over
///    a sweep of wall angles: 0.105 mm at 4.9 cm).
///  - A vertical cylinder of radius ρ whose axis is D from the sensor reads at most
///    r (Δ/2)^2 D / (2ρ) too far: 0.64 mm at r = 5 cm for ρ >= 1 cm (D <= 6 cm); measured
///    0.59 mm. The off-plane rays of the rings help thinner poles (measured 0.95 mm for
///    ρ = 3 mm at 4.9 cm), but poles much thinner than the ~3 mm ray spacing at 5 cm can read
///    worse or be missed.
///  - Off the horizontal plane (a pitched sensor, sloped surfaces) the edge point may fall
///    between azimuths π/azimuths apart: a plane then reads at most
///    r δ / (cos(θ - h) - δ), δ = sin h sin θ (1 - cos(π / azimuths)), too far, under 1 mm at
///    5 cm while θ - h <= 75°.
#pragma once

#include <limits>
#include <memory>
#include <vector>

#include "epuck_vrep_compat/world/types.hpp"

namespace evc {

struct Body;

/// Mount and cone of one proximity sensor (a plain value type).
struct ConeSensor {
  Vec3 position_m = Vec3::Zero();       ///< mount in the body frame, metres (z from ground)
  double yaw_rad = 0.0;                 ///< axis heading in the body frame
  double pitch_rad = 0.0;               ///< axis tilt, positive down
  double half_angle_rad = 0.2617993878; ///< cone half angle (15°)
  double min_range_m = 0.0015;          ///< readings closer than this read min_range_m
  double max_range_m = 0.05;            ///< detection range; "nothing" reads max_range_m
  int rings = 2;                        ///< rings of rays around the axis
  int azimuths = 16;                    ///< rays per ring (even, so 0 and π are sampled)
};

/// Throws std::invalid_argument unless the sensor is usable: finite mount, 0 <= half angle <
/// π/2, 0 <= min_range_m < max_range_m (finite), rings >= 0, azimuths even and >= 2.
void validate_cone_sensor(const ConeSensor& sensor);

/// Sensor-to-body rotation: yaw about z, then pitch about the new y.
Quat sensor_orientation(const ConeSensor& sensor);

/// Unit ray directions in the sensor frame: the axis first, then ring by ring.
std::vector<Vec3> cone_ray_directions(const ConeSensor& sensor);

/// The closest hit of one cone.
struct ConeReading {
  double distance_m = std::numeric_limits<double>::infinity();  ///< +inf: nothing in the cone
  int handle = -1;                  ///< object detected, -1 for none
  Vec3 point_m = Vec3::Zero();      ///< detected point, sensor frame (zero for none)
  Vec3 normal = Vec3::Zero();       ///< its outward surface normal, sensor frame (zero for none)
};

/// A body a cone may see, with a sphere about its origin that encloses it (radius rounded up)
/// and, when known, a half-space that holds it: computed once per robot, then culled against
/// each of its cones.
struct ConeCandidate {
  const Body* body = nullptr;
  Vec3 centre_m = Vec3::Zero();  ///< the body's origin, world frame
  double radius_m = 0.0;
  /// Every point p of the body has p · away >= beyond_m (the plane through its point closest
  /// to a viewpoint, square to the way there, moved toward the viewpoint by a little more than
  /// rounding); away is unit, or zero when the viewpoint touches the body (no half-space).
  Vec3 away = Vec3::Zero();
  double beyond_m = 0.0;
};

/// @p body as a candidate, where it is now (no half-space yet).
ConeCandidate cone_candidate(const Body& body);

/// Gives @p candidate the half-space that holds its body, seen from @p viewpoint; returns the
/// distance from @p viewpoint to the body less rounding (<= 0: touching, and no half-space).
double bound_candidate(ConeCandidate& candidate, const Vec3& viewpoint);

/// Reads cones. It keeps its working lists from one read to the next, so that reading
/// allocates nothing; one reader per thread.
class ConeReader {
 public:
  ConeReader();
  ~ConeReader();
  ConeReader(ConeReader&&) noexcept;
  ConeReader& operator=(ConeReader&&) noexcept;

  /// Reads one cone against candidate bodies (what lies around the robot, in handle order);
  /// only candidates whose bounding spheres and half-spaces reach into the cone are
  /// ray-tested, and only the rays that may still beat the best hit so far are cast. Candidates
  /// that cannot be seen change nothing: the reading is the shortest hit over the rays, the
  /// earliest ray on a tie. @p sensor_pose is the sensor frame in the world; @p directions
  /// come from cone_ray_directions(sensor) (their layout, axis then rings, is relied on).
  ConeReading read(const std::vector<ConeCandidate>& candidates, const Pose& sensor_pose,
                   const ConeSensor& sensor, const std::vector<Vec3>& directions);

  /// read in two halves, for a caller that can find the sensor's frame cheaply but not
  /// exactly: cull keeps the candidates that may reach into the cone of a sensor at
  /// @p position_m looking along @p axis (unit, world frame), and says whether any is left.
  /// Both may be off by rounding (a few units in the last place of the exact frame's), which
  /// the cull's slack covers, so the candidates it keeps are those read would test or more,
  /// and the reading is the same. read_culled then reads what the last cull kept, from the
  /// exact frame @p sensor_pose (whose bits reach the reading).
  bool cull(const std::vector<ConeCandidate>& candidates, const Vec3& position_m,
            const Vec3& axis, const ConeSensor& sensor);
  ConeReading read_culled(const Pose& sensor_pose, const ConeSensor& sensor,
                          const std::vector<Vec3>& directions);

  struct Scratch;  // defined where it is used

 private:
  std::unique_ptr<Scratch> scratch_;
};

}  // namespace evc
