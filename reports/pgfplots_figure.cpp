#include "reports/pgfplots_figure.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "reports/axis_ticks.h"
#include "reports/figure_style.h"
#include "reports/latex_text.h"

namespace fscil {

namespace {

// The axis box without its labels, in centimetres: bar widths are computed from it.
constexpr double axis_width_cm = 7, axis_height_cm = 4.6;

const std::array<const char*, figure_dash_kinds> pgf_dashes = {"solid", "dashed", "dotted", "dashdotted",
                                                                "densely dashed"};
// The marks of render_svg's markers, drawn solid whatever the line's dash pattern.
const std::array<const char*, figure_marker_kinds> pgf_marks = {
    "mark=*, mark options={solid}",          "mark=square*, mark options={solid}",
    "mark=triangle*, mark options={solid}",  "mark=diamond*, mark options={solid}",
    "mark=triangle*, mark options={solid, rotate=180}", "mark=o, mark options={solid}",
    "mark=square, mark options={solid}",     "mark=x, mark options={solid}"};

// A label as LaTeX text: latex_text's characters, and those a title or legend may hold beyond a
// name's (braces would unbalance the key=value list the text sits in).
std::string latex_label(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '\\': out += "\\textbackslash{}"; break;
      case '{': out += "\\{"; break;
      case '}': out += "\\}"; break;
      case '~': out += "\\textasciitilde{}"; break;
      case '^': out += "\\textasciicircum{}"; break;
      case '<': out += "\\textless{}"; break;
      case '>': out += "\\textgreater{}"; break;
      case '|': out += "\\textbar{}"; break;
      case '\n': case '\r': case '\t': out += ' '; break;
      default: out += latex_text(std::string(1, c));
    }
  }
  return out;
}

std::string pgf_number(double value) { return fmt::format("{:.8g}", value); }

std::string colour_name(std::size_t index) { return fmt::format("fscilfigure{}", index); }

// Limits giving one unit the same length on both axes of the axis box. pgfplots' own `axis equal`
// overflows TeX's dimensions when the two ranges differ by orders of magnitude; these never do.
std::string equal_unit_limits(const Figure& figure) {
  const double infinity = std::numeric_limits<double>::infinity();
  double x_low = infinity, x_high = -infinity, y_low = infinity, y_high = -infinity;
  for (const auto& series : figure.series) {
    for (std::size_t i = 0; i < series.x.size(); ++i) {
      if (!std::isfinite(series.x[i]) || !std::isfinite(series.y[i])) continue;
      x_low = std::min(x_low, series.x[i]);
      x_high = std::max(x_high, series.x[i]);
      y_low = std::min(y_low, series.y[i]);
      y_high = std::max(y_high, series.y[i]);
    }
  }
  if (figure.draw_unit_circle) {
    x_low = std::min(x_low, -1.0);
    x_high = std::max(x_high, 1.0);
    y_low = std::min(y_low, -1.0);
    y_high = std::max(y_high, 1.0);
  }
  const AxisTicks x = padded_value_axis(x_low, x_high, -HUGE_VAL, HUGE_VAL),
                  y = padded_value_axis(y_low, y_high, figure.y_floor, figure.y_ceiling);
  const double units_per_cm = std::max((x.high - x.low) / axis_width_cm, (y.high - y.low) / axis_height_cm);
  const double x_centre = (x.low + x.high) / 2, y_centre = (y.low + y.high) / 2;
  const double x_half = units_per_cm * axis_width_cm / 2, y_half = units_per_cm * axis_height_cm / 2;
  return fmt::format("xmin={}, xmax={}, ymin={}, ymax={}", pgf_number(x_centre - x_half), pgf_number(x_centre + x_half),
                     pgf_number(y_centre - y_half), pgf_number(y_centre + y_half));
}

// The y axis as the SVG draws it (padded_value_axis): its ends and its ticks.
std::string value_axis_limits(const Figure& figure) {
  auto [low, high] = value_range(figure);
  const bool bars = figure.kind == FigureKind::bars;
  if (bars) low = std::min(low, 0.0), high = std::max(high, 0.0);
  const AxisTicks y = padded_value_axis(low, high, figure.y_floor, figure.y_ceiling, !(bars && low == 0),
                                        !(bars && high == 0));
  std::vector<std::string> ticks;
  for (const double value : y.values) ticks.push_back(pgf_number(value));
  return fmt::format("ymin={}, ymax={}, ytick={{{}}}", pgf_number(y.low), pgf_number(y.high), fmt::join(ticks, ","));
}

bool has_legend(const Figure& figure) {
  return std::any_of(figure.series.begin(), figure.series.end(),
                     [](const FigureSeries& series) { return !series.label.empty(); });
}

std::string axis_options(const Figure& figure) {
  std::vector<std::string> options = {fmt::format("scale only axis, width={}cm, height={}cm", axis_width_cm, axis_height_cm)};
  if (!figure.title.empty() || !figure.note.empty()) {
    std::string title = latex_label(figure.title);
    if (!figure.note.empty()) {
      title += fmt::format("{}{{\\footnotesize\\itshape {}}}", figure.title.empty() ? "" : "\\\\", latex_label(figure.note));
    }
    options.push_back(fmt::format("title style={{align=center}}, title={{{}}}", title));
  }
  if (!figure.x_label.empty()) options.push_back(fmt::format("xlabel={{{}}}", latex_label(figure.x_label)));
  if (!figure.y_label.empty()) options.push_back(fmt::format("ylabel={{{}}}", latex_label(figure.y_label)));
  options.push_back("ymajorgrids, unbounded coords=jump");
  if (has_legend(figure)) options.push_back("legend pos=outer north east, legend cell align={left}");
  const std::size_t categories = figure.x_categories.size();
  if (categories > 0) {
    std::vector<std::string> ticks, labels;
    std::size_t widest = 0;
    for (std::size_t c = 0; c < categories; ++c) {
      ticks.push_back(std::to_string(c));
      labels.push_back("{" + latex_label(figure.x_categories[c]) + "}");
      widest = std::max(widest, figure.x_categories[c].size());
    }
    options.push_back(fmt::format("xtick={{{}}}, xticklabels={{{}}}, xmin=-0.5, xmax={}", fmt::join(ticks, ","),
                                  fmt::join(labels, ","), pgf_number(static_cast<double>(categories) - 0.5)));
    // About 0.18 cm per character of an axis label: slant them when they would run into each other.
    if (0.18 * static_cast<double>(widest) > axis_width_cm / static_cast<double>(categories)) {
      options.push_back("x tick label style={rotate=35, anchor=north east}");
    }
  }
  if (figure.x_log) {
    const auto [low, high] = x_range(figure);
    const AxisTicks x = padded_log_axis(low, high);
    std::vector<std::string> ticks;
    for (const double value : x.values) ticks.push_back(pgf_number(value));
    options.push_back(fmt::format("xmode=log, log basis x=10, log ticks with fixed point, xmin={}, xmax={}, xtick={{{}}}",
                                  pgf_number(x.low), pgf_number(x.high), fmt::join(ticks, ",")));
  }
  if (figure.kind == FigureKind::bars) {
    const double bar_width = 0.8 * axis_width_cm / static_cast<double>(categories) /
                             static_cast<double>(std::max<std::size_t>(1, figure.series.size()));
    options.push_back(fmt::format("ybar=0pt, bar width={:.3f}cm", bar_width));
  }
  if (figure.equal_axes && categories == 0) {
    options.push_back(equal_unit_limits(figure));
  } else {
    options.push_back(value_axis_limits(figure));
  }
  return fmt::format("{}", fmt::join(options, ",\n  "));
}

std::string plot_options(const Figure& figure, std::size_t index) {
  const SeriesStyle style = series_style(index);
  const std::string colour = colour_name(index);
  std::string options;
  switch (figure.kind) {
    case FigureKind::bars: options = fmt::format("fill={}, draw=black", colour); break;
    case FigureKind::scatter: options = fmt::format("only marks, color={}, {}", colour, pgf_marks[style.marker]); break;
    case FigureKind::lines:
      options = fmt::format("color={}, {}, thick, {}", colour, pgf_dashes[style.dash], pgf_marks[style.marker]);
      break;
  }
  if (has_spread(figure.series[index])) {
    // Last: the keys after /.cd are error bars' own.
    options += fmt::format(", error bars/.cd, y dir=both, y explicit, error bar style={{solid, thin, {}}}",
                           figure.kind == FigureKind::bars ? "black" : colour);
  }
  return options;
}

// A line's gap stays a `nan` point, where unbounded coords=jump breaks it; bars and points are
// left out.
std::string coordinates(const Figure& figure, const FigureSeries& series) {
  std::vector<std::string> points;
  const bool spread = has_spread(series);
  for (std::size_t i = 0; i < series.x.size(); ++i) {
    const bool finite = std::isfinite(series.x[i]) && std::isfinite(series.y[i]);
    if (finite) {
      std::string point = fmt::format("({},{})", pgf_number(series.x[i]), pgf_number(series.y[i]));
      // A plot with error bars needs a spread at every point: 0 where it has none.
      if (spread) {
        const auto [bottom, top] = whisker_ends(figure, series, i);
        const bool drawn = std::isfinite(bottom) && std::isfinite(top);
        point += fmt::format(" += (0,{}) -= (0,{})", pgf_number(drawn ? top - series.y[i] : 0),
                             pgf_number(drawn ? series.y[i] - bottom : 0));
      }
      points.push_back(point);
    } else if (figure.kind == FigureKind::lines && std::isfinite(series.x[i])) {
      points.push_back(fmt::format("({},nan)", pgf_number(series.x[i])));
    }
  }
  return fmt::format("{}", fmt::join(points, " "));
}

}  // namespace

std::string render_pgfplots(const Figure& figure) {
  require_valid_figure(figure);
  std::string out = fmt::format(
      "% fscil-bench figure {}: \\input it in a document that loads \\usepackage{{pgfplots}}\n"
      "% (with \\pgfplotsset{{compat=1.16}} or newer). The axis box is {}cm x {}cm; scale the whole\n"
      "% picture, e.g. \\resizebox{{\\columnwidth}}{{!}}{{\\input{{...}}}}, as bar widths are absolute.\n",
      figure.name, axis_width_cm, axis_height_cm);
  if (!figure.note.empty()) {
    std::string note = figure.note;
    std::replace_if(note.begin(), note.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
    out += fmt::format("% Note: {}\n", note);
  }
  out += "\\begin{tikzpicture}\n";
  for (std::size_t s = 0; s < figure.series.size(); ++s) {
    out += fmt::format("\\definecolor{{{}}}{{HTML}}{{{}}}\n", colour_name(s), series_style(s).colour);
  }
  out += fmt::format("\\begin{{axis}}[\n  {}\n]\n", axis_options(figure));
  if (figure.draw_unit_circle) {
    out += "\\addplot[forget plot, gray, dashed, no marks, domain=0:360, samples=91] ({cos(x)}, {sin(x)});\n";
  }
  const bool labelled = has_legend(figure);
  for (std::size_t s = 0; s < figure.series.size(); ++s) {
    out += fmt::format("\\addplot[{}] coordinates {{{}}};\n", plot_options(figure, s), coordinates(figure, figure.series[s]));
    // pgfplots pairs legend entries with plots by count, so an unlabelled series still takes one.
    if (labelled) out += fmt::format("\\addlegendentry{{{}}}\n", latex_label(figure.series[s].label));
  }
  out += "\\end{axis}\n\\end{tikzpicture}\n";
  return out;
}

}  // namespace fscil
