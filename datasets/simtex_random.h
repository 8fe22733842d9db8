#pragma once
#include <cstdint>
#include <random>

#include "core/random_draws.h"

namespace fscil::simtex_random {

enum Purpose : std::uint64_t { family = 1, material = 2, device = 3, nominal_context = 4, recording_context = 5,
                               recording_signal = 6, operator_habit = 7 };

inline std::mt19937_64 generator(std::uint64_t seed, Purpose purpose, std::uint64_t a, std::uint64_t b = 0) {
  return derived_generator(seed, purpose, a, b);
}

// The simulator's draws, fixed algorithms (core/random_draws.h) so a seed gives the same data
// on any standard library.
inline double uniform(std::mt19937_64& rng, double low, double high) { return uniform_real(rng, low, high); }
inline double normal(std::mt19937_64& rng) { return fscil::normal(rng, 0.0, 1.0); }
inline int pick(std::mt19937_64& rng, int count) { return static_cast<int>(uniform_int(rng, 0, count - 1)); }

}  // namespace fscil::simtex_random
