#pragma once
#include <cstddef>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace fscil {

// One named line, bar group member or point cloud of a figure. A non-finite x or y (NaN) is a gap:
// a line breaks there, a bar or point is not drawn.
struct FigureSeries {
  std::string label;  // legend entry; empty for none
  std::vector<double> x, y;
  // The spread of each y over seeds (one standard deviation), drawn as a whisker from y - s to
  // y + s: empty for none, else one per y (NaN where a point has none, e.g. a single seed).
  std::vector<double> y_spread = {};
};

enum class FigureKind { lines, bars, scatter };

// A plain description of one figure panel, rendered as SVG, pgfplots and CSV from the same data.
struct Figure {
  std::string name;  // file stem: lower-case letters, digits, '_' and '-'
  std::string title, x_label, y_label;
  FigureKind kind = FigureKind::lines;
  // When not empty, x is categorical: these name the categories and each finite x is the index of
  // one (0 .. size - 1). Bars are always categorical.
  std::vector<std::string> x_categories;
  std::vector<FigureSeries> series;
  // The y quantity's natural bounds (accuracy 0 and 100, R and times 0 and none): no tick beyond them.
  double y_floor = -std::numeric_limits<double>::infinity(), y_ceiling = std::numeric_limits<double>::infinity();
  // A numeric x on a logarithmic (base 10) axis, for values spanning decades (N_ps 5 to 1000);
  // every finite x must then be positive.
  bool x_log = false;
  bool equal_axes = false;        // one unit is as long on x as on y (points on the unit circle)
  bool draw_unit_circle = false;  // x^2 + y^2 = 1, under the data
  // Shown under the title when not empty, e.g. "selected on test (inflated)": a figure must carry
  // its own caveat, as it travels without the page or paper text around it.
  std::string note;
};

// The widest legend entry and x category label a renderer shows whole, in characters; wider ones
// are cut. Figures built from runs keep their labels within them (series_labels.h).
inline constexpr std::size_t figure_legend_width = 28, figure_category_width = 20;
// Characters (UTF-8 code points) of `text`: what a label's width is counted in.
std::size_t code_points(const std::string& text);

// Whether the series, or any series of `figure`, has a finite spread to draw.
bool has_spread(const FigureSeries& series);
bool has_spread(const Figure& figure);
// The ends of point i's whisker, y -/+ its spread cut at the quantity's natural bounds (an
// accuracy's whisker stops at 100); NaN for both where the point has no spread.
std::pair<double, double> whisker_ends(const Figure& figure, const FigureSeries& series, std::size_t i);
// The lowest and highest finite x over every series. Infinite (low > high) when there is none.
std::pair<double, double> x_range(const Figure& figure);
// The lowest and highest finite y - spread and y + spread over every series (y alone where there
// is no spread): what the value axis must cover. Infinite (low > high) when there is no point.
std::pair<double, double> value_range(const Figure& figure);

// Throws ReportError naming the figure when it cannot be rendered: a name that is not a file stem,
// a series whose x and y differ in length (or whose spread is neither empty nor one per y, or
// negative), a categorical x that is not a category's index, bars without categories, an x that is
// not positive on a logarithmic axis, or a logarithmic axis that is categorical.
void require_valid_figure(const Figure& figure);

}  // namespace fscil
