#include "datasets/finite_values.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace fscil {

// A per-sample std::isfinite test took a tenth of the front end's time; this loop vectorises.
__attribute__((target_clones("avx2", "default"))) bool all_finite(const float* values, std::int64_t count) {
  // A float is finite when its exponent bits are not all ones.
  std::int32_t infinite = 0;
  for (std::int64_t i = 0; i < count; ++i) {
    std::int32_t bits;
    std::memcpy(&bits, values + i, sizeof bits);
    infinite |= static_cast<std::int32_t>((bits & 0x7f800000) == 0x7f800000);
  }
  return infinite == 0;
}

std::int64_t first_non_finite(const float* values, std::int64_t count) {
  if (all_finite(values, count)) return -1;
  return std::find_if(values, values + count, [](float x) { return !std::isfinite(x); }) - values;
}

}  // namespace fscil
