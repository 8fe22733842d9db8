#pragma once
#include <string>
#include <vector>

namespace fscil {

// The ticks of one figure axis, at "nice" numbers (1, 2 or 5 times a power of ten); the axis runs
// from the first tick to the last, so it covers every value it was made for.
struct AxisTicks {
  double low = 0, high = 1;
  double step = 1;
  std::vector<double> values;
  int decimals = 0;  // digits after the point that tell two neighbouring ticks apart
};

// About `target_count` ticks covering [low, high]. A single value gets an axis around it, and
// non-finite bounds (no data) the axis 0 to 1.
AxisTicks nice_ticks(double low, double high, int target_count = 6);
// The ticks of `step` (from nice_ticks) inside [low, high], for an axis widened to keep units equal.
AxisTicks ticks_within(double low, double high, double step);
// A tick's label with the ticks' decimals; never "-0".
std::string tick_label(double value, int decimals);

}  // namespace fscil
