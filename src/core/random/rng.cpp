#include "epuck_vrep_compat/random/rng.hpp"

#include <cmath>

namespace evc {
namespace {

constexpr double kTwoPi = 6.283185307179586476925286766559;

// The splitmix64 output function alone, for mixing values that are not a running state.
std::uint64_t mix(std::uint64_t x) {
  std::uint64_t state = x;
  return splitmix64(state);
}

}  // namespace

std::uint64_t splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

std::uint64_t derive_seed(std::uint64_t seed, std::uint64_t robot_index, std::uint64_t stream_id) {
  // Chained rather than XORed together so (index, stream) pairs cannot cancel each other.
  return mix(mix(mix(seed) ^ robot_index) ^ stream_id);
}

Rng::Rng(std::uint64_t seed) {
  std::uint64_t state = seed;
  for (auto& word : s_) word = splitmix64(state);
}

double Rng::normal() {
  const double u1 = uniform();
  const double u2 = uniform();
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(kTwoPi * u2);
}

std::uint64_t Rng::state_digest() const {
  std::uint64_t digest = 0;
  for (const auto word : s_) digest = mix(digest ^ word);
  return digest;
}

}  // namespace evc
