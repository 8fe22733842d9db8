#include "reports/figure_csv.h"

#include <fmt/format.h>

#include <cmath>

#include "core/csv_text.h"

namespace fscil {

namespace {

std::string csv_number(double value) { return std::isfinite(value) ? fmt::format("{:.8g}", value) : ""; }

}  // namespace

std::string render_figure_csv(const Figure& figure) {
  require_valid_figure(figure);
  // y_std, the spread over seeds, only where the figure draws one (empty where a point has none).
  const bool spread = has_spread(figure);
  std::string out = spread ? "series,x,y,y_std\n" : "series,x,y\n";
  for (const auto& series : figure.series) {
    for (std::size_t i = 0; i < series.x.size(); ++i) {
      const double x = series.x[i];
      const std::string x_text = figure.x_categories.empty() || !std::isfinite(x)
                                     ? csv_number(x)
                                     : csv_field(figure.x_categories[static_cast<std::size_t>(x)]);
      out += fmt::format("{},{},{}", csv_field(series.label), x_text, csv_number(series.y[i]));
      if (spread) out += "," + csv_number(i < series.y_spread.size() ? series.y_spread[i] : NAN);
      out += "\n";
    }
  }
  return out;
}

}  // namespace fscil
