#include "epuck_vrep_compat/epuck/cone_sensor.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "epuck_vrep_compat/world/collision_world.hpp"
#include "world/body.hpp"
#include "world/bullet_conversions.hpp"

namespace evc {
namespace {
constexpr double kPi = 3.14159265358979323846;

// The rays' layout: ray (ring r, azimuth j) is (ring_cos[r], ring_sin[r] azimuth_cos[j],
// ring_sin[r] azimuth_sin[j]), after the axis.
struct RayLayout {
  std::vector<double> ring_cos, ring_sin, azimuth_cos, azimuth_sin;
};

void lay_out_rays(const ConeSensor& sensor, RayLayout& layout) {
  layout.ring_cos.clear();
  layout.ring_sin.clear();
  layout.azimuth_cos.clear();
  layout.azimuth_sin.clear();
  for (int ring = 1; ring <= sensor.rings; ++ring) {
    const double polar = sensor.half_angle_rad * ring / sensor.rings;
    layout.ring_cos.push_back(std::cos(polar));
    layout.ring_sin.push_back(std::sin(polar));
  }
  for (int j = 0; j < sensor.azimuths; ++j) {
    const double azimuth = 2.0 * kPi * j / sensor.azimuths;
    layout.azimuth_cos.push_back(std::cos(azimuth));
    // Exact zeros at azimuths 0 and pi keep those rays in the horizontal plane.
    layout.azimuth_sin.push_back((2 * j == sensor.azimuths || j == 0) ? 0.0 : std::sin(azimuth));
  }
}
}  // namespace

void validate_cone_sensor(const ConeSensor& sensor) {
  if (!sensor.position_m.allFinite() || !std::isfinite(sensor.yaw_rad) ||
      !std::isfinite(sensor.pitch_rad)) {
    throw std::invalid_argument("sensor position, yaw_rad and pitch_rad must be finite");
  }
  if (!(sensor.half_angle_rad >= 0.0 && sensor.half_angle_rad < 0.5 * kPi)) {
    throw std::invalid_argument("half_angle_rad must be in [0, pi/2)");
  }
  if (!(sensor.min_range_m >= 0.0 && sensor.min_range_m < sensor.max_range_m &&
        std::isfinite(sensor.max_range_m))) {
    throw std::invalid_argument("need 0 <= min_range_m < max_range_m, both finite");
  }
  if (sensor.rings < 0) throw std::invalid_argument("rings must be >= 0");
  if (sensor.azimuths < 2 || sensor.azimuths % 2 != 0) {
    throw std::invalid_argument("azimuths must be even and >= 2 (0 and pi are sampled)");
  }
}

Quat sensor_orientation(const ConeSensor& sensor) {
  return Quat(Eigen::AngleAxisd(sensor.yaw_rad, Vec3::UnitZ()) *
              Eigen::AngleAxisd(sensor.pitch_rad, Vec3::UnitY()));
}

std::vector<Vec3> cone_ray_directions(const ConeSensor& sensor) {
  RayLayout layout;
  lay_out_rays(sensor, layout);
  std::vector<Vec3> directions;
  directions.reserve(1 + layout.ring_cos.size() * layout.azimuth_cos.size());
  directions.emplace_back(Vec3::UnitX());
  for (std::size_t r = 0; r < layout.ring_cos.size(); ++r) {
    for (std::size_t j = 0; j < layout.azimuth_cos.size(); ++j) {
      directions.emplace_back(layout.ring_cos[r], layout.ring_sin[r] * layout.azimuth_cos[j],
                              layout.ring_sin[r] * layout.azimuth_sin[j]);
    }
  }
  return directions;
}

namespace {

// Radius of a sphere about a body's origin that encloses it, rounded up so that the cull
// below never drops a body that a ray can hit.
double enclosing_radius(const Primitive& shape) {
  double squared = shape.radius_m * shape.radius_m;
  if (shape.kind == Primitive::Kind::kBox) squared = shape.half_extents.length2();
  if (shape.kind == Primitive::Kind::kCylinder) {
    squared += shape.half_height_m * shape.half_height_m;
  }
  return std::sqrt(squared) * (1.0 + 1e-12);
}

}  // namespace

ConeCandidate cone_candidate(const Body& body) {
  return ConeCandidate{&body, to_eigen(body.object->getWorldTransform().getOrigin()),
                       enclosing_radius(body.primitive)};
}

double bound_candidate(ConeCandidate& candidate, const Vec3& viewpoint) {
  const RayTarget target = ray_target(*candidate.body, viewpoint);
  candidate.away.setZero();
  candidate.beyond_m = 0.0;
  if (target.min_distance_m > 0.0) {
    // ray_target's distance is short of the closest point by more than its rounding; the
    // plane's offset gives up a little more for the products' rounding (far more than it).
    candidate.away = to_eigen(target.toward);
    candidate.beyond_m = viewpoint.dot(candidate.away) + target.min_distance_m -
                         1e-9 * (1.0 + viewpoint.cwiseAbs().maxCoeff());
  }
  return target.min_distance_m;
}

// What a cone reads with, kept by its reader so that reading a cone allocates nothing.
struct ConeReader::Scratch {
  std::vector<const Body*> in_cone;
  std::vector<RayTarget> targets;
  std::vector<Vec3> per_metre;  // per target: toward / min_distance_m, sensor frame
  std::vector<double> paces;    // per ray, see hit_paces
  bool touching = false;        // some target touches the sensor
  double half_angle_rad = -1.0;  // the angle cos_h and sin_h belong to
  double cos_h = 0.0, sin_h = 0.0;
  // The rays' layout (lay_out_rays, as cone_ray_directions lays them out) for the sampling
  // it was made for.
  double layout_half_angle_rad = -1.0;
  int layout_rings = -1, layout_azimuths = -1;
  RayLayout layout;
  std::vector<double> lean;  // per azimuth, see cast_one_target
};

ConeReader::ConeReader() : scratch_(std::make_unique<Scratch>()) {}
ConeReader::~ConeReader() = default;
ConeReader::ConeReader(ConeReader&&) noexcept = default;
ConeReader& ConeReader::operator=(ConeReader&&) noexcept = default;

namespace {

using ConeScratch = ConeReader::Scratch;

// Keeps the candidates that may reach into the cone: most of a robot's neighbours lie beside
// or behind a given sensor, and a ray test costs more than these checks.
// - Its bounding sphere: a sphere of radius R whose centre is d > R away reaches into the cone
//   when the centre is at most h + asin(R / d) off the axis; both angles lie in [0, pi), so in
//   cosines:
//     offset · axis + R sin h >= d cos(h + asin(R / d)) + R sin h = cos h sqrt(d^2 - R^2),
//   compared squared when the left side is positive (it is read with a little slack, so that
//   rounding keeps a body rather than drops it).
// - Its half-space {p : p · away >= beyond} (a wall's sphere is large, its half-space is not):
//   the cone's points within range, s + r u (0 <= r <= range, u at most h off the axis), reach
//   at most s · away + range max(0, cos(max(0, theta - h))) along away, theta the axis's angle
//   to away; cos(theta - h) = cos theta cos h + sin theta sin h. (The half-space already gives
//   up more than the rounding here, see cone_candidate.)
// The frame (@p position, @p axis) may be off by rounding: 1e-12 m more reach and the slack
// below cover far more than that.
void cull_to_cone(const std::vector<ConeCandidate>& candidates, const Vec3& position,
                  const Vec3& axis, const ConeSensor& sensor, ConeScratch& scratch) {
  scratch.in_cone.clear();
  for (const ConeCandidate& candidate : candidates) {
    const double radius = candidate.radius_m;
    const Vec3 offset = candidate.centre_m - position;
    const double reach = sensor.max_range_m + radius + 1e-12;
    const double squared = offset.squaredNorm();
    if (squared > reach * reach) continue;
    const double lhs = offset.dot(axis) + scratch.sin_h * radius + 1e-12 * reach;
    const double inside = squared - radius * radius;  // d^2 - R^2
    if (inside > 0.0 && (lhs < 0.0 || lhs * lhs < scratch.cos_h * scratch.cos_h * inside)) {
      continue;
    }
    const double cos_theta = axis.dot(candidate.away);
    const double farthest =
        cos_theta >= scratch.cos_h
            ? 1.0
            : cos_theta * scratch.cos_h +
                  std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta)) * scratch.sin_h;
    if (position.dot(candidate.away) +
            sensor.max_range_m * std::max(0.0, farthest) < candidate.beyond_m) {
      continue;
    }
    scratch.in_cone.push_back(candidate.body);
  }
}

// How soon each ray (unit, sensor frame) may hit a target: target j lies beyond a plane
// min_distance_m away along toward_j, which ray d reaches after min_distance_m / (d · toward_j)
// metres, or never if d · toward_j <= 0. So no hit of ray k is nearer than 1 / s_k, with
//     s_k = max_j (d_k · toward_j) / min_distance_j,
// and none at all if s_k <= 0. per_metre holds each target's toward_j / min_distance_j in the
// sensor frame (@p rotation: sensor to world), unless a target touches the sensor.
void per_metre_steps(const Eigen::Matrix3d& rotation, ConeScratch& scratch) {
  const std::vector<RayTarget>& targets = scratch.targets;
  std::vector<Vec3>& per_metre = scratch.per_metre;
  per_metre.clear();
  bool touching = false;
  for (const RayTarget& target : targets) {
    if (target.min_distance_m <= 0.0) {
      touching = true;
      continue;
    }
    // (Paces only decide which rays are cast: rounding them differently changes no reading,
    // since min_distance_m gives up far more than that.)
    per_metre.push_back(rotation.transpose() * to_eigen(target.toward) *
                        (1.0 / target.min_distance_m));
  }
  scratch.touching = touching;
}

// Each ray's s_k (see per_metre_steps); returns the ray with the largest (the first on a tie),
// or ray 0 when a target touches the sensor: any ray may then hit at 0, and the first one wins.
std::size_t hit_paces(const std::vector<Vec3>& directions, ConeScratch& scratch) {
  const std::vector<Vec3>& per_metre = scratch.per_metre;
  std::vector<double>& paces = scratch.paces;
  const std::size_t count = directions.size();
  paces.resize(count);
  double* pace = paces.data();
  std::size_t fastest = 0;
  double top = -std::numeric_limits<double>::infinity();
  const auto keep = [&](std::size_t k, double value) {
    pace[k] = value;
    const bool faster = value > top;  // without a branch: which ray wins varies
    fastest = faster ? k : fastest;
    top = faster ? value : top;
  };
  if (per_metre.size() == 1) {  // the usual case: one target (a wall, a robot)
    const Vec3 step = per_metre.front();
    for (std::size_t k = 0; k < count; ++k) keep(k, directions[k].dot(step));
  } else {
    for (std::size_t k = 0; k < count; ++k) {
      double value = -std::numeric_limits<double>::infinity();
      for (const Vec3& step : per_metre) value = std::max(value, directions[k].dot(step));
      keep(k, value);
    }
  }
  return scratch.touching ? 0 : fastest;
}

// Casts ray @p first, then every other ray of @p count in turn that may still beat the best
// hit so far (a shorter hit, or an equal one from an earlier ray): @p may_hit(k, limit,
// strictly) says whether ray k may hit within limit (only nearer than it if strictly).
template <typename MayHit, typename Cast>
void cast_in_turn(std::size_t first, std::size_t count, double range, const ConeReading& best,
                  const std::size_t& best_ray, MayHit may_hit, Cast cast) {
  double limit = range;  // min(best.distance_m, range), kept up to date
  if (may_hit(first, limit, false)) {
    cast(first, limit);
    limit = std::min(best.distance_m, range);
  }
  for (std::size_t k = 0; k < count; ++k) {
    if (!may_hit(k, limit, false) || k == first ||
        (k > best_ray && !may_hit(k, best.distance_m, true))) {
      continue;
    }
    cast(k, limit);
    limit = std::min(best.distance_m, range);
  }
}

// Keeps the layout of @p sensor's rays, as cone_ray_directions lays them out.
void cache_layout(const ConeSensor& sensor, ConeScratch& scratch) {
  if (scratch.layout_half_angle_rad == sensor.half_angle_rad &&
      scratch.layout_rings == sensor.rings && scratch.layout_azimuths == sensor.azimuths) {
    return;
  }
  scratch.layout_half_angle_rad = sensor.half_angle_rad;
  scratch.layout_rings = sensor.rings;
  scratch.layout_azimuths = sensor.azimuths;
  lay_out_rays(sensor, scratch.layout);
}

// cast_in_turn for one target that does not touch the sensor (the usual case: a wall, a
// robot), without a pace per ray: ray (r, j)'s pace is c_r s_x + s_r lean_j, with
// lean_j = cos a_j s_y + sin a_j s_z (@p step = s, see per_metre_steps; c_r, s_r the ring's cosine
// and sine, s_r >= 0). So the azimuth that leans most toward the target leads in every ring
// (each product and sum rounds monotonically, so this holds of the rounded paces too): the
// fastest ray is the axis or that azimuth in some ring, and a ring whose leading ray may not hit
// within the limit is skipped whole. These paces round otherwise than hit_paces' (which
// changes no reading, see there).
//
// Within a ring, lean_j = |(s_y, s_z)| cos(a_j - phi) falls with the azimuth's angle from the
// lead either way round, so the rays are visited from the lead outward on each side until one
// cannot hit within the limit even with 1e-12 of slack: every ray farther on that side leans
// less, to rounding (a few units in the last place of |s| limit), so it could not either. A
// ray that may win has pace x limit above 1 by far more than that rounding: min_distance_m
// gives up 1e-9 m or more (ray_target), 1e-9 / min_distance_m of it. The rays are cast in
// another order than ray by ray, which changes no reading (see cast_in_turn).
template <typename Cast>
void cast_one_target(const Vec3& step, double range, ConeScratch& scratch,
                     const ConeReading& best, const std::size_t& best_ray, Cast cast) {
  const std::size_t azimuths = scratch.layout.azimuth_cos.size();
  std::vector<double>& leans = scratch.lean;
  leans.resize(azimuths);
  double* lean = leans.data();
  const double* azimuth_cos = scratch.layout.azimuth_cos.data();
  const double* azimuth_sin = scratch.layout.azimuth_sin.data();
  const double s_y = step.y(), s_z = step.z();
  for (std::size_t j = 0; j < azimuths; ++j) lean[j] = azimuth_cos[j] * s_y + azimuth_sin[j] * s_z;
  // The largest lean, in four independent chains (the order of a maximum changes nothing),
  // then the first azimuth that has it.
  double tops[4] = {lean[0], lean[0], lean[0], lean[0]};
  for (std::size_t j = 0; j < azimuths; ++j) tops[j % 4] = std::max(tops[j % 4], lean[j]);
  const double top = std::max(std::max(tops[0], tops[1]), std::max(tops[2], tops[3]));
  std::size_t lead = 0;
  while (lead + 1 < azimuths && !(lean[lead] == top)) ++lead;
  std::size_t first = 0;
  double first_pace = step.x();
  for (std::size_t r = 0; r < scratch.layout.ring_cos.size(); ++r) {
    const double pace = scratch.layout.ring_cos[r] * step.x() + scratch.layout.ring_sin[r] * top;
    if (pace > first_pace) {
      first = 1 + r * azimuths + lead;
      first_pace = pace;
    }
  }
  double limit = range;  // min(best.distance_m, range), kept up to date
  if (first_pace * limit >= 1.0) {
    cast(first, limit);
    limit = std::min(best.distance_m, range);
  }
  const auto visit = [&](std::size_t k, double pace) {
    if (!(pace * limit >= 1.0) || k == first ||
        (k > best_ray && !(pace * best.distance_m > 1.0))) {
      return;
    }
    cast(k, limit);
    limit = std::min(best.distance_m, range);
  };
  visit(0, step.x());
  const std::size_t half = azimuths / 2;
  for (std::size_t r = 0; r < scratch.layout.ring_cos.size(); ++r) {
    const double along = scratch.layout.ring_cos[r] * step.x();
    const double across = scratch.layout.ring_sin[r];
    if (!((along + across * top) * limit >= 1.0)) continue;  // not even the leading ray
    const std::size_t ring = 1 + r * azimuths;
    const auto walk = [&](std::size_t j) {  // false: none farther on this side may hit
      const double pace = along + across * lean[j];
      if (pace * limit < 1.0 - 1e-12) return false;
      visit(ring + j, pace);
      return true;
    };
    walk(lead);
    for (std::size_t d = 1; d <= half && walk((lead + d) % azimuths); ++d) {
    }
    for (std::size_t d = 1; d < half && walk((lead + azimuths - d) % azimuths); ++d) {
    }
  }
}

}  // namespace

ConeReading ConeReader::read(const std::vector<ConeCandidate>& candidates,
                             const Pose& sensor_pose, const ConeSensor& sensor,
                             const std::vector<Vec3>& directions) {
  if (!cull(candidates, sensor_pose.position_m, sensor_pose.orientation * Vec3::UnitX(),
            sensor)) {
    return ConeReading();
  }
  return read_culled(sensor_pose, sensor, directions);
}

bool ConeReader::cull(const std::vector<ConeCandidate>& candidates, const Vec3& position_m,
                      const Vec3& axis, const ConeSensor& sensor) {
  ConeScratch& scratch = *scratch_;
  if (scratch.half_angle_rad != sensor.half_angle_rad) {
    scratch.half_angle_rad = sensor.half_angle_rad;
    scratch.cos_h = std::cos(sensor.half_angle_rad);
    scratch.sin_h = std::sin(sensor.half_angle_rad);
  }
  cull_to_cone(candidates, position_m, axis, sensor, scratch);
  return !scratch.in_cone.empty();
}

ConeReading ConeReader::read_culled(const Pose& sensor_pose, const ConeSensor& sensor,
                                    const std::vector<Vec3>& directions) {
  ConeReading best;
  ConeScratch& scratch = *scratch_;
  std::vector<RayTarget>& targets = scratch.targets;
  targets.clear();
  for (const Body* body : scratch.in_cone) {
    const RayTarget target = ray_target(*body, sensor_pose.position_m);
    if (target.min_distance_m <= sensor.max_range_m) targets.push_back(target);
  }
  if (targets.empty()) return best;
  const Eigen::Matrix3d rotation = sensor_pose.orientation.toRotationMatrix();
  per_metre_steps(rotation, scratch);
  // The reading is the shortest hit over the rays, the earliest ray on a tie. The ray that may
  // hit soonest usually finds it at once; every ray that cannot beat the best so far is then
  // skipped, which changes nothing. The checks are inline: most rays stop at them.
  std::size_t best_ray = directions.size();
  const auto cast = [&](std::size_t k, double limit) {
    const RayHit hit = ray_cast_targets(targets, rotation * directions[k], limit);
    // Ray k wins with a shorter hit, or an equal one if it comes earlier.
    if (hit.handle < 0 || hit.distance_m > best.distance_m ||
        (hit.distance_m == best.distance_m && k > best_ray)) {
      return;
    }
    best_ray = k;
    best.distance_m = hit.distance_m;
    best.handle = hit.handle;
    best.point_m = directions[k] * hit.distance_m;
    best.normal = rotation.transpose() * hit.normal;
  };
  const std::size_t count = directions.size();
  if (!scratch.touching && scratch.per_metre.size() == 1 &&
      count == 1 + static_cast<std::size_t>(sensor.rings) * sensor.azimuths) {
    cache_layout(sensor, scratch);
    cast_one_target(scratch.per_metre.front(), sensor.max_range_m, scratch, best, best_ray, cast);
    return best;
  }
  const std::size_t first = hit_paces(directions, scratch);
  if (scratch.touching) {
    // Any ray may hit at 0, so every ray may hit within any limit, and nearer than one above 0.
    cast_in_turn(first, count, sensor.max_range_m, best, best_ray,
                 [](std::size_t, double limit, bool strictly) { return !strictly || limit > 0.0; },
                 cast);
  } else {
    const double* pace = scratch.paces.data();
    cast_in_turn(first, count, sensor.max_range_m, best, best_ray,
                 [pace](std::size_t k, double limit, bool strictly) {
                   const double reach = pace[k] * limit;
                   return strictly ? reach > 1.0 : reach >= 1.0;
                 },
                 cast);
  }
  return best;
}

}  // namespace evc
