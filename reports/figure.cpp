#include "reports/figure.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/shown_text.h"
#include "core/error.h"

namespace fscil {

namespace {

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

void require_valid_figure(const Figure& figure) {
  if (!is_file_stem(figure.name)) {
    throw ReportError(fmt::format("figure name '{}' is not a file stem of a-z, 0-9, '_' and '-'",
                                  shown_text(figure.name)));
  }
  const auto fail = [&](const std::string& why) {
    throw ReportError(fmt::format("figure '{}': {}", figure.name, why));
  };
  if (figure.kind == FigureKind::bars && figure.x_categories.empty()) fail("bars need x_categories");
  const double categories = static_cast<double>(figure.x_categories.size());
  for (const auto& series : figure.series) {
    if (series.x.size() != series.y.size()) {
      fail(fmt::format("series '{}' has {} x and {} y values", shown_text(series.label), series.x.size(),
                       series.y.size()));
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
