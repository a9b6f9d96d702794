// Internal: standard normal draws by the ziggurat method (Marsaglia & Tsang 2000, with
// Doornik's 2005 fix: the strip index and the uniform come from different bits), for noise on
// whole images, where Rng::normal's log, sqrt and cosine per draw would cost more than the
// rest of the model. 128 strips; about 98.8% of draws cost one Rng output and a multiply.
// Deterministic like Rng itself: the same generator state gives the same draws.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>

#include "epuck_vrep_compat/random/rng.hpp"

namespace evc {

constexpr int kZigguratStrips = 128;

// Strip i spans |x| < edge[i] at heights between the density at edge[i] and at edge[i + 1];
// strip 0 is the base, a rectangle standing in for the box under r plus the tail beyond it.
// ratio[i] = edge[i + 1] / edge[i]: inside it a draw needs no density test.
struct ZigguratTables {
  std::array<double, kZigguratStrips + 1> edge{};
  std::array<double, kZigguratStrips> ratio{};
  ZigguratTables();
};

// The tables, built once.
const ZigguratTables& ziggurat_tables();

// A standard normal from @p rng (one or more of its outputs).
double ziggurat_normal(Rng& rng);

// The draw's rarer half (about 1.2% of draws), given the first output @p bits that the fast
// path of ziggurat_normal_inline could not use: the same draws ziggurat_normal makes then.
double ziggurat_normal_rest(Rng& rng, std::uint64_t bits);

// ziggurat_normal, its common path inlined in a loop over many draws (an image's pixels):
// the same outputs of @p rng, the same values.
inline double ziggurat_normal_inline(Rng& rng, const ZigguratTables& t) {
  const std::uint64_t bits = rng.next_u64();
  // The top 53 bits give u in [-1, 1); the low 7 bits, unused by u, pick the strip.
  const double u = static_cast<double>(bits >> 11) * 0x1.0p-52 - 1.0;
  const int strip = static_cast<int>(bits & (kZigguratStrips - 1));
  if (std::abs(u) < t.ratio[strip]) return u * t.edge[strip];
  return ziggurat_normal_rest(rng, bits);
}

}  // namespace evc
