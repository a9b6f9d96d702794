/// @file
/// The core's only source of randomness: a seeded xoshiro256** generator.
///
/// Written here rather than taken from <random> because the standard distributions are not
/// specified bit for bit, so a run would not replay across standard libraries. Every noise source
/// of every robot owns one Rng derived from (seed, robot index, stream id), so one robot's draws
/// never depend on how many draws another robot made.
#pragma once

#include <cstdint>

namespace evc {

/// One step of splitmix64: advances @p state and returns a well-mixed 64-bit value.
std::uint64_t splitmix64(std::uint64_t& state);

/// Derives an independent generator seed from a master seed, a robot index and a stream id.
/// Each input passes through splitmix64 mixing, so neighbouring indices give unrelated seeds.
std::uint64_t derive_seed(std::uint64_t seed, std::uint64_t robot_index, std::uint64_t stream_id);

/// xoshiro256** (Blackman & Vigna), seeded by four splitmix64 outputs of the seed.
class Rng {
 public:
  /// Seeds the generator; any 64-bit value (including 0) gives a valid state.
  explicit Rng(std::uint64_t seed = 0);

  /// The next raw 64-bit output.
  std::uint64_t next_u64() {
    const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }

  /// Skips @p count raw outputs: the state next_u64 would leave after as many calls.
  void discard(std::uint64_t count) {
    for (; count > 0; --count) next_u64();
  }

  /// Uniform in (0, 1]: the top 53 bits plus one, times 2^-53. Never 0, so log(u) is finite.
  /// (Defined here, as next_u64 is, so that the per-sensor draws of a step are inlined.)
  double uniform() { return static_cast<double>((next_u64() >> 11) + 1) * 0x1.0p-53; }

  /// Standard normal by Box–Muller as in the e-puck noise model: X = sqrt(-2 ln U1) cos(2π U2).
  /// Consumes two uniforms per call and uses the cosine branch only, so replays stay simple.
  double normal();

  /// A 64-bit digest of the state, for determinism tests.
  std::uint64_t state_digest() const;

 private:
  static std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

  std::uint64_t s_[4];
};

}  // namespace evc
