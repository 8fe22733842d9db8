#include "core/valid_range.h"

#include <fmt/format.h>

#include <cmath>

namespace fscil {

bool ValidRange::contains(double value) const {
  if (!std::isfinite(value)) return false;
  const bool above_low = low_open_ ? value > low_ : value >= low_;
  const bool below_high = high_open_ ? value < high_ : value <= high_;
  return above_low && below_high;
}

std::string ValidRange::describe() const {
  const bool bounded_below = std::isfinite(low_), bounded_above = std::isfinite(high_);
  if (bounded_below && bounded_above) {
    return fmt::format("in {}{}, {}{}", low_open_ ? '(' : '[', low_, high_, high_open_ ? ')' : ']');
  }
  if (bounded_below) return fmt::format("{} {}", low_open_ ? ">" : ">=", low_);
  if (bounded_above) return fmt::format("{} {}", high_open_ ? "<" : "<=", high_);
  return "finite";
}

}  // namespace fscil
