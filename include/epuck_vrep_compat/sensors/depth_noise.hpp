/// @file
/// Axial noise of a Kinect v1 depth image (models.md §6).
///
/// Equation: for a depth z (metres, along the optical axis) below far_m and n ~ N(0, 1),
///
///     σ_z(z) = a + b (z - c)²
///     z'     = z + σ_z(z) n
///     z'     = 1 / (k round(1 / (k z')))   if k > 0 (k = inverse_depth_step_per_m)
///     out    = clamp(z', near_m, far_m);   out = far_m where z >= far_m (no return)
///
/// with Nguyen, Izadi & Lovell's (2012) a = 0.0012 m, b = 0.0019 m⁻¹, c = 0.4 m by default
/// (σ_z = 0.041 m at 5 m; models.md marks the constants as from memory).
///
/// The optional quantisation rounds 1/z to a grid of step k, as the Kinect rounds disparity:
/// disparity steps of δ px at focal length f px and baseline B metres give k = δ / (f B), so
/// depth steps of k z²; the Kinect's δ = 1/8 px, f ≈ 580 px, B ≈ 0.075 m give k ≈ 2.87e-3 m⁻¹
/// (7 cm steps at 5 m). It is off (k = 0) by default.
///
/// One Rng owned by the model draws n for every pixel in row-major order, far ones included,
/// so the same seed and image give the same noisy image, bit for bit. The draws use the
/// ziggurat method (src/core/random/ziggurat.hpp): measured here, a VGA frame costs ~2.3 ms
/// (numpy's normals alone: ~3 ms; bench/cell_sensors.py).
#pragma once

#include <cstddef>
#include <cstdint>

#include "epuck_vrep_compat/random/rng.hpp"

namespace evc {

/// Parameters of the depth noise model (metres unless stated).
struct DepthNoiseSpec {
  double a_m = 0.0012;                   ///< σ_z at z = c
  double b_per_m = 0.0019;               ///< growth of σ_z with (z - c)²
  double c_m = 0.4;                      ///< depth of the smallest σ_z
  double inverse_depth_step_per_m = 0.0; ///< k: quantisation step of 1/z, 0 = off
};

/// A seeded depth noise model.
class DepthNoise {
 public:
  /// Throws std::invalid_argument unless a_m, b_per_m and inverse_depth_step_per_m are finite
  /// and >= 0 and c_m is finite.
  explicit DepthNoise(const DepthNoiseSpec& spec = DepthNoiseSpec(), std::uint64_t seed = 0);

  /// Writes the noisy version of @p count depths from @p depth_m to @p out_m (which may be the
  /// same buffer). Throws std::invalid_argument unless 0 <= near_m < far_m, both finite, and
  /// every depth is >= 0 (+inf reads as no return); nothing is drawn then.
  void apply(const float* depth_m, float* out_m, std::size_t count, double near_m,
             double far_m);

  /// σ_z(z), metres.
  double sigma_m(double depth_m) const;

  /// Restarts the noise stream from @p seed.
  void reseed(std::uint64_t seed) { rng_ = Rng(seed); }

  const DepthNoiseSpec& spec() const { return spec_; }

 private:
  DepthNoiseSpec spec_;
  Rng rng_;
};

}  // namespace evc
