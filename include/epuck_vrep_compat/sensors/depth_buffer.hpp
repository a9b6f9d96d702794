/// @file
/// V-REP's depth buffer of a vision sensor (simGetVisionSensorDepthBuffer): the depth image's
/// values mapped to 0..1 between the near and far clipping planes, the bottom row first.
///
///     out[r][c] = float(clamp((double(depth_m[H - 1 - r][c]) - near_m) / (far_m - near_m), 0, 1))
///
/// computed in double and rounded once to float: bit for bit what numpy gives for
/// ``np.clip((depth[::-1].astype(np.float64) - near_m) / (far_m - near_m), 0, 1)`` cast to
/// float32 (a NaN stays NaN, +inf becomes 1), in one pass and without the float64 copy.
#pragma once

#include <cstddef>

namespace evc {

/// Writes V-REP's depth buffer of the @p height x @p width depth image @p depth_m (metres,
/// row 0 at the top, row-major) to @p out (row 0 = the image's bottom row). Throws
/// std::invalid_argument unless near_m and far_m are finite and near_m < far_m; @p out must
/// not overlap @p depth_m.
void vrep_depth_buffer(const float* depth_m, float* out, std::size_t height, std::size_t width,
                       double near_m, double far_m);

}  // namespace evc
