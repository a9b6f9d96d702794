#include "ziggurat.hpp"

#include <array>
#include <cmath>
#include <cstdint>

namespace evc {
namespace {

constexpr int kStrips = kZigguratStrips;
constexpr double kTailStart = 3.442619855899;     // r: where the base strip's tail begins
constexpr double kStripArea = 9.91256303526217e-3;  // v: the area of every strip

double density(double x) { return std::exp(-0.5 * x * x); }

// A draw beyond r from the normal's tail (Marsaglia 1964), with the sign given.
double tail(Rng& rng, bool negative) {
  double x = 0.0, y = 0.0;
  do {
    x = std::log(rng.uniform()) / kTailStart;
    y = std::log(rng.uniform());
  } while (-2.0 * y < x * x);
  return negative ? x - kTailStart : kTailStart - x;
}

}  // namespace

ZigguratTables::ZigguratTables() {
  double f = density(kTailStart);
  edge[0] = kStripArea / f;
  edge[1] = kTailStart;
  edge[kStrips] = 0.0;
  for (int i = 2; i < kStrips; ++i) {
    edge[i] = std::sqrt(-2.0 * std::log(kStripArea / edge[i - 1] + f));
    f = density(edge[i]);
  }
  for (int i = 0; i < kStrips; ++i) ratio[i] = edge[i + 1] / edge[i];
}

const ZigguratTables& ziggurat_tables() {
  static const ZigguratTables instance;
  return instance;
}

double ziggurat_normal(Rng& rng) {
  return ziggurat_normal_inline(rng, ziggurat_tables());
}

double ziggurat_normal_rest(Rng& rng, std::uint64_t bits) {
  const ZigguratTables& t = ziggurat_tables();
  for (;;) {
    const double u = static_cast<double>(bits >> 11) * 0x1.0p-52 - 1.0;
    const int strip = static_cast<int>(bits & (kStrips - 1));
    if (std::abs(u) < t.ratio[strip]) return u * t.edge[strip];
    if (strip == 0) return tail(rng, u < 0.0);
    // The wedge beside the strip's core: accept x under the density.
    const double x = u * t.edge[strip];
    const double outer = density(t.edge[strip]) / density(x);
    const double inner = density(t.edge[strip + 1]) / density(x);
    if (inner + rng.uniform() * (outer - inner) < 1.0) return x;
    bits = rng.next_u64();
  }
}

}  // namespace evc
