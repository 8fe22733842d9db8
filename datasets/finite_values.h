#pragma once
#include <cstdint>

namespace fscil {

// The index of the first NaN or infinite value among `count` floats, or -1 when all are finite.
// The common all-finite case is one branch-free, vectorised pass.
std::int64_t first_non_finite(const float* values, std::int64_t count);
// Whether all `count` floats are finite: that pass alone.
bool all_finite(const float* values, std::int64_t count);

}  // namespace fscil
