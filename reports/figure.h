#pragma once
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

namespace fscil {

// One named line, bar group member or point cloud of a figure. A non-finite x or y (NaN) is a gap:
// a line breaks there, a bar or point is not drawn.
struct FigureSeries {
  std::string label;  // legend entry; empty for none
  std::vector<double> x, y;
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

// Throws ReportError naming the figure when it cannot be rendered: a name that is not a file stem,
// a series whose x and y differ in length, a categorical x that is not a category's index, bars
// without categories.
void require_valid_figure(const Figure& figure);

}  // namespace fscil
