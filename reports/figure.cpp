#include "reports/figure.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/shown_text.h"
#include "core/error.h"

namespace fscil {

namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();

bool is_file_stem(const std::string& name) {
  if (name.empty()) return false;
  for (const char c : name) {
    const bool allowed = (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
    if (!allowed) return false;
  }
  return true;
}

}  // namespace

std::size_t code_points(const std::string& text) {
  return static_cast<std::size_t>(std::count_if(text.begin(), text.end(), [](char c) { return (c & 0xC0) != 0x80; }));
}

bool has_spread(const FigureSeries& series) {
  return std::any_of(series.y_spread.begin(), series.y_spread.end(), [](double s) { return std::isfinite(s); });
}

bool has_spread(const Figure& figure) {
  return std::any_of(figure.series.begin(), figure.series.end(),
                     [](const FigureSeries& series) { return has_spread(series); });
}

std::pair<double, double> whisker_ends(const Figure& figure, const FigureSeries& series, std::size_t i) {
  const double y = series.y[i];
  if (i >= series.y_spread.size() || !std::isfinite(series.y_spread[i]) || !std::isfinite(y)) return {kNaN, kNaN};
  const double spread = series.y_spread[i];
  return {std::max(y - spread, std::min(y, figure.y_floor)), std::min(y + spread, std::max(y, figure.y_ceiling))};
}

std::pair<double, double> x_range(const Figure& figure) {
  double low = HUGE_VAL, high = -HUGE_VAL;
  for (const auto& series : figure.series) {
    for (const double x : series.x) {
      if (std::isfinite(x)) low = std::min(low, x), high = std::max(high, x);
    }
  }
  return {low, high};
}

std::pair<double, double> value_range(const Figure& figure) {
  double low = HUGE_VAL, high = -HUGE_VAL;
  for (const auto& series : figure.series) {
    for (std::size_t i = 0; i < series.y.size(); ++i) {
      const double y = series.y[i];
      if (!std::isfinite(y)) continue;
      const auto [bottom, top] = whisker_ends(figure, series, i);
      low = std::min(low, std::isfinite(bottom) ? bottom : y);
      high = std::max(high, std::isfinite(top) ? top : y);
    }
  }
  return {low, high};
}

void require_valid_figure(const Figure& figure) {
  if (!is_file_stem(figure.name)) {
    throw ReportError(fmt::format("figure name '{}' is not a file stem of a-z, 0-9, '_' and '-'",
                                  shown_text(figure.name)));
  }
  const auto fail = [&](const std::string& why) {
    throw ReportError(fmt::format("figure '{}': {}", figure.name, why));
  };
  if (figure.kind == FigureKind::bars && figure.x_categories.empty()) fail("bars need x_categories");
  if (figure.x_log && !figure.x_categories.empty()) fail("a logarithmic x axis cannot be categorical");
  const double categories = static_cast<double>(figure.x_categories.size());
  for (const auto& series : figure.series) {
    if (series.x.size() != series.y.size()) {
      fail(fmt::format("series '{}' has {} x and {} y values", shown_text(series.label), series.x.size(),
                       series.y.size()));
    }
    if (!series.y_spread.empty() && series.y_spread.size() != series.y.size()) {
      fail(fmt::format("series '{}' has {} spreads for {} y values", shown_text(series.label), series.y_spread.size(),
                       series.y.size()));
    }
    for (const double spread : series.y_spread) {
      if (spread < 0) fail(fmt::format("series '{}' has a negative spread {}", shown_text(series.label), spread));
    }
    if (figure.x_log) {
      for (const double x : series.x) {
        if (std::isfinite(x) && x <= 0) {
          fail(fmt::format("series '{}' has x = {} on a logarithmic axis", shown_text(series.label), x));
        }
      }
    }
    if (figure.x_categories.empty()) continue;
    for (const double x : series.x) {
      if (std::isfinite(x) && (x != std::floor(x) || x < 0 || x >= categories)) {
        fail(fmt::format("series '{}' has x = {} but the {} categories are numbered 0 to {}", shown_text(series.label),
                         x, figure.x_categories.size(), figure.x_categories.size() - 1));
      }
    }
  }
}

}  // namespace fscil
