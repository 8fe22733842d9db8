#pragma once
#include <cstdint>
#include <random>
#include <utility>
#include <vector>

#include "core/random_draws.h"

namespace fscil {

// Each protocol draw gets its own stream derived from the run seed, so adding a draw in one
// place never shifts the numbers drawn in another.
enum class SeedPurpose : std::uint64_t { class_order = 1, split = 2, shots = 3, training = 4 };

inline std::mt19937_64 seeded_generator(std::uint64_t seed, SeedPurpose purpose, std::uint64_t salt = 0) {
  std::seed_seq sequence{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32),
                         static_cast<std::uint32_t>(purpose), static_cast<std::uint32_t>(salt)};
  return std::mt19937_64(sequence);
}

// Fisher-Yates with our own index draws: std::shuffle's draw pattern is not specified. Each index
// is the engine's output modulo i, drawn again in the rare case (probability < i / 2^64) that
// would bias it.
template <typename T>
void shuffle_with(std::vector<T>& values, std::mt19937_64& generator) {
  for (std::size_t i = values.size(); i > 1; --i) {
    const std::size_t j = uniform_index(generator, i);
    std::swap(values[i - 1], values[j]);
  }
}

template <typename T>
void seeded_shuffle(std::vector<T>& values, std::uint64_t seed, SeedPurpose purpose, std::uint64_t salt = 0) {
  auto generator = seeded_generator(seed, purpose, salt);
  shuffle_with(values, generator);
}

}  // namespace fscil
