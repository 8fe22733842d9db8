#include "reports/axis_ticks.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace fscil {

namespace {

// 1, 2, 5 or 10 times a power of ten near `value` (Heckbert, "Nice numbers for graph labels").
double nice_number(double value, bool round_to_nearest) {
  const double exponent = std::floor(std::log10(value));
  const double power = std::pow(10.0, exponent);
  const double fraction = value / power;
  double nice = 10;
  if (round_to_nearest) {
    nice = fraction < 1.5 ? 1 : fraction < 3 ? 2 : fraction < 7 ? 5 : 10;
  } else {
    nice = fraction <= 1 ? 1 : fraction <= 2 ? 2 : fraction <= 5 ? 5 : 10;
  }
  return nice * power;
}

int decimals_of(double step) { return std::max(0, static_cast<int>(-std::floor(std::log10(step) + 1e-9))); }

// Ticks at multiples of `step` from `first` to `last` (both multiples), without floating-point dust.
std::vector<double> multiples(double first, double last, double step) {
  std::vector<double> values;
  // No ticks rather than a thousand, or multiples past 2^53 steps that are no longer whole steps.
  if (!(std::abs(first / step) < 9e15 && std::abs(last / step) < 9e15) || last - first > 1000 * step) return values;
  const long long from = std::llround(first / step), to = std::llround(last / step);
  for (long long k = from; k <= to; ++k) values.push_back(static_cast<double>(k) * step);
  return values;
}

}  // namespace

AxisTicks nice_ticks(double low, double high, int target_count) {
  if (!std::isfinite(low) || !std::isfinite(high)) low = 0, high = 1;
  if (high < low) std::swap(low, high);
  if (high - low <= std::abs(high) * 1e-12) {
    const double pad = low == 0 ? 1 : std::abs(low) * 0.1;
    low -= pad;
    high += pad;
  }
  AxisTicks ticks;
  const double range = nice_number(high - low, false);
  ticks.step = nice_number(range / std::max(1, target_count - 1), true);
  ticks.low = std::floor(low / ticks.step) * ticks.step;
  ticks.high = std::ceil(high / ticks.step) * ticks.step;
  ticks.values = multiples(ticks.low, ticks.high, ticks.step);
  ticks.decimals = decimals_of(ticks.step);
  return ticks;
}

AxisTicks padded_value_axis(double low, double high, double floor, double ceiling, bool pad_low, bool pad_high) {
  AxisTicks ticks = nice_ticks(low, high);
  const double data_low = std::isfinite(low) ? std::min(low, high) : ticks.low;
  const double data_high = std::isfinite(high) ? std::max(low, high) : ticks.high;
  // Bounds the data respect: ticks beyond them would show values the quantity cannot take.
  if (data_low >= floor && ticks.low < floor) ticks.low = floor;
  if (data_high <= ceiling && ticks.high > ceiling) ticks.high = ceiling;
  ticks.values.erase(std::remove_if(ticks.values.begin(), ticks.values.end(),
                                    [&](double value) { return value < ticks.low - 1e-9 * ticks.step ||
                                                               value > ticks.high + 1e-9 * ticks.step; }),
                     ticks.values.end());
  const double pad = 0.04 * (ticks.high - ticks.low);
  if (pad_low) ticks.low -= pad;
  if (pad_high) ticks.high += pad;
  return ticks;
}

AxisTicks padded_log_axis(double low, double high) {
  if (!(std::isfinite(low) && std::isfinite(high) && low > 0 && high > 0)) low = 1, high = 10;
  if (high < low) std::swap(low, high);
  const double first = std::log10(low), last = std::log10(high);
  const double pad = std::max(0.04 * (last - first), 0.05);
  AxisTicks ticks;
  ticks.low = std::pow(10.0, first - pad);
  ticks.high = std::pow(10.0, last + pad);
  ticks.step = 10;
  // Powers of ten where the axis holds two of them; 1, 2 and 5 times them on a shorter one.
  for (const std::vector<double>& mantissas : {std::vector<double>{1}, std::vector<double>{1, 2, 5}}) {
    ticks.values.clear();
    for (int power = static_cast<int>(std::floor(first - pad)); power <= static_cast<int>(std::ceil(last + pad)); ++power) {
      for (const double mantissa : mantissas) {
        const double value = mantissa * std::pow(10.0, power);
        if (value >= ticks.low * (1 - 1e-12) && value <= ticks.high * (1 + 1e-12)) ticks.values.push_back(value);
      }
    }
    if (ticks.values.size() >= 2) break;
  }
  ticks.decimals = ticks.values.empty() ? 0 : decimals_of(ticks.values.front());
  return ticks;
}

AxisTicks ticks_within(double low, double high, double step) {
  AxisTicks ticks;
  ticks.low = low;
  ticks.high = high;
  ticks.step = step;
  ticks.values = multiples(std::ceil(low / step - 1e-9) * step, std::floor(high / step + 1e-9) * step, step);
  ticks.decimals = decimals_of(step);
  return ticks;
}

std::string tick_label(double value, int decimals) {
  std::string label = fmt::format("{:.{}f}", value, decimals);
  if (label.find_first_not_of("-0.") == std::string::npos && label[0] == '-') label.erase(0, 1);
  return label;
}

}  // namespace fscil
