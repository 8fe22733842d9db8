#pragma once
#include <cstdint>
#include <random>

namespace fscil {

// Every random number the harness draws itself (simulated data, splits, shots, augmentation,
// probes) comes from these functions. std::mt19937_64 and std::seed_seq are fixed by the standard,
// but the std:: distributions are not: libstdc++ has changed their algorithms before, which would
// change the data a seed gives. These are fixed algorithms, so a seed gives the same numbers on any
// standard library. Each call's consumption of the engine depends only on the engine's state
// (nothing is cached between calls). Bad arguments throw ProtocolError.

// splitmix64's finaliser: spreads a 64-bit value over all bits.
inline std::uint64_t splitmix64(std::uint64_t value) {
  value += 0x9e3779b97f4a7c15ULL;
  value = (value ^ (value >> 30)) * 0xbf58476d1ce4e5b9ULL;
  value = (value ^ (value >> 27)) * 0x94d049bb133111ebULL;
  return value ^ (value >> 31);
}

// An engine of its own for each (purpose, a, b) under one seed, so a generated dataset's every
// draw is fixed by the seed alone, whatever the order or thread that makes it. Purposes are the
// caller's numbers; two datasets may reuse them, as their seeds never meet.
inline std::mt19937_64 derived_generator(std::uint64_t seed, std::uint64_t purpose, std::uint64_t a = 0,
                                         std::uint64_t b = 0) {
  return std::mt19937_64(splitmix64(splitmix64(splitmix64(seed ^ purpose) + a) + b));
}

// Uniform in [a, b) from one draw: the top 53 bits of the engine's output scaled by 2^-53.
double uniform_real(std::mt19937_64& generator, double a, double b);

// Uniform in {0, ..., n - 1} without bias: the engine's output modulo n, drawn again while that
// output is below 2^64 mod n.
std::uint64_t uniform_index(std::mt19937_64& generator, std::uint64_t n);

// Uniform in {lo, ..., hi}, both ends included (as std::uniform_int_distribution(lo, hi)).
std::int64_t uniform_int(std::mt19937_64& generator, std::int64_t lo, std::int64_t hi);

// Normal(mean, stddev) by Marsaglia's polar method.
double normal(std::mt19937_64& generator, double mean, double stddev);

// Gamma(shape, scale) by Marsaglia and Tsang's method (mean shape * scale).
double gamma(std::mt19937_64& generator, double shape, double scale);

// Beta(a, b) as X / (X + Y) with X ~ Gamma(a, 1) drawn before Y ~ Gamma(b, 1).
double beta(std::mt19937_64& generator, double a, double b);

// True with probability p: one uniform_real(0, 1) below p.
bool bernoulli(std::mt19937_64& generator, double p);

}  // namespace fscil
