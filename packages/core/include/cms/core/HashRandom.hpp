// Reproducible pseudo-random numbers keyed by (global id, salt): the same
// value for a DOF whatever rank owns it, so start vectors, probes and test
// structures are identical on any number of ranks. A stateless splitmix64
// hash: seeding a std::mt19937 per entry cost ~5 us each, which dominated
// start-up at 1e6 DOFs (doc/benchmarks.md).
#pragma once

#include <cstdint>

namespace cms {

/// Uniform in [0, 1).
inline double hashUnit(std::uint64_t key, std::uint64_t salt) {
  std::uint64_t z = key * 0x9E3779B97F4A7C15ull + salt * 0xD1B54A32D192ED03ull + 0x632BE59BD9B4E019ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) * 0x1.0p-53;
}

/// Uniform in [-1, 1).
inline double hashSigned(std::uint64_t key, std::uint64_t salt) {
  return 2.0 * hashUnit(key, salt) - 1.0;
}

}  // namespace cms
