#include "core/random_draws.h"

#include <fmt/format.h>

#include <cmath>
#include <limits>

#include "core/error.h"

namespace fscil {

double uniform_real(std::mt19937_64& generator, double a, double b) {
  if (!(a <= b) || !std::isfinite(b - a)) throw ProtocolError(fmt::format("uniform_real: bad range [{}, {})", a, b));
  const double unit = static_cast<double>(generator() >> 11) * 0x1.0p-53;
  const double value = a + (b - a) * unit;
  return value < b ? value : std::nextafter(b, a);  // rounding reaches b when b - a is tiny beside |a|
}

// Rejecting the lowest 2^64 mod n of the 2^64 outputs leaves a multiple of n, so the output modulo
// n is exactly uniform (OpenBSD's arc4random_uniform rule). A rejection has probability below
// n / 2^64, so in practice the index is the first output modulo n: the plain modulo that the
// splits were drawn with, which Lemire's multiply-and-shift would not keep.
std::uint64_t uniform_index(std::mt19937_64& generator, std::uint64_t n) {
  if (n == 0) throw ProtocolError("uniform_index: no index to draw from an empty range");
  const std::uint64_t rejected_below = (0 - n) % n;  // (2^64 - n) mod n == 2^64 mod n
  std::uint64_t draw = generator();
  while (draw < rejected_below) draw = generator();
  return draw % n;
}

std::int64_t uniform_int(std::mt19937_64& generator, std::int64_t lo, std::int64_t hi) {
  if (lo > hi) throw ProtocolError(fmt::format("uniform_int: empty range [{}, {}]", lo, hi));
  const std::uint64_t span = static_cast<std::uint64_t>(hi) - static_cast<std::uint64_t>(lo);  // no overflow
  const std::uint64_t offset =
      span == std::numeric_limits<std::uint64_t>::max() ? generator() : uniform_index(generator, span + 1);
  return static_cast<std::int64_t>(static_cast<std::uint64_t>(lo) + offset);
}

// The polar method makes normals in pairs; the second, v * factor, is dropped rather than kept for
// the next call, so that what a call draws depends only on the engine.
double normal(std::mt19937_64& generator, double mean, double stddev) {
  if (!(stddev >= 0)) throw ProtocolError(fmt::format("normal: standard deviation {} is not >= 0", stddev));
  double u = 0, v = 0, s = 0;
  do {
    u = uniform_real(generator, -1, 1);
    v = uniform_real(generator, -1, 1);
    s = u * u + v * v;
  } while (s >= 1 || s == 0);
  const double factor = std::sqrt(-2 * std::log(s) / s);
  return mean + stddev * u * factor;
}

// G. Marsaglia and W. W. Tsang, "A simple method for generating gamma variables" (2000): a normal
// x proposes d (1 + c x)^3, accepted by a squeeze test, then by the exact log test. Shapes below 1
// draw Gamma(shape + 1) and multiply by U^(1 / shape), the paper's boost.
double gamma(std::mt19937_64& generator, double shape, double scale) {
  if (!(shape > 0) || !(scale > 0) || !std::isfinite(shape) || !std::isfinite(scale)) {
    throw ProtocolError(fmt::format("gamma: shape {} and scale {} must be finite and > 0", shape, scale));
  }
  if (shape < 1) {
    const double boosted = gamma(generator, shape + 1, scale);
    return boosted * std::pow(uniform_real(generator, 0, 1), 1 / shape);
  }
  const double d = shape - 1.0 / 3, c = 1 / std::sqrt(9 * d);
  while (true) {
    const double x = normal(generator, 0, 1);
    const double root = 1 + c * x;
    if (root <= 0) continue;
    const double v = root * root * root;
    const double u = uniform_real(generator, 0, 1);
    if (u < 1 - 0.0331 * x * x * x * x || std::log(u) < 0.5 * x * x + d * (1 - v + std::log(v))) return scale * d * v;
  }
}

double beta(std::mt19937_64& generator, double a, double b) {
  const double x = gamma(generator, a, 1);
  const double y = gamma(generator, b, 1);
  return x + y > 0 ? x / (x + y) : 0.5;  // tiny a and b can underflow both draws to 0: not NaN
}

bool bernoulli(std::mt19937_64& generator, double p) {
  if (!(p >= 0 && p <= 1)) throw ProtocolError(fmt::format("bernoulli: probability {} is not in [0, 1]", p));
  return uniform_real(generator, 0, 1) < p;
}

}  // namespace fscil
