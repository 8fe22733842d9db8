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
// The one value-axis rule of every figure: nice_ticks over the data [low, high], none outside the
// quantity's natural bounds [floor, ceiling] (an accuracy is never below 0 nor above 100), and the
// axis reaching 4% of its span past the outer ticks (where `pad_low`, `pad_high`), so a point on
// the first or last tick does not sit on the frame. A bar chart's baseline 0 takes no padding.
AxisTicks padded_value_axis(double low, double high, double floor, double ceiling, bool pad_low = true,
                            bool pad_high = true);
// A logarithmic (base 10) axis over the positive data [low, high], reaching 4% of its span in
// decades past them (at least 0.05 decade): ticks at powers of ten where it holds two, else at 1, 2
// and 5 times them; `step` is 10, `low`, `high` and `values` are values, not logarithms. Data that
// are not positive and finite get the axis 1 to 10.
AxisTicks padded_log_axis(double low, double high);
// The ticks of `step` (from nice_ticks) inside [low, high], for an axis widened to keep units equal.
AxisTicks ticks_within(double low, double high, double step);
// A tick's label with the ticks' decimals; never "-0".
std::string tick_label(double value, int decimals);

}  // namespace fscil
