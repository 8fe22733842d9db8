#include "reports/svg_figure.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "reports/axis_ticks.h"
#include "reports/figure_style.h"
#include "reports/xml_text.h"

namespace fscil {

namespace {

constexpr double page_width = 640, min_page_height = 400;
// Average advance of an 11-pixel sans-serif character: sizes margins and legend without font metrics.
constexpr double char_width = 6.6;
constexpr double legend_row = 18;

const std::array<const char*, figure_dash_kinds> svg_dashes = {"", "7,3", "1.5,2.5", "9,3,2,3", "4,2"};

std::string px(double value) { return fmt::format("{:.2f}", value); }

// At most `limit` characters, the cut marked with an ellipsis; never splits a UTF-8 sequence.
std::string shortened(const std::string& text, std::size_t limit) {
  if (code_points(text) <= limit) return text;
  std::size_t kept = 0, end = 0;
  while (end < text.size()) {
    if ((text[end] & 0xC0) != 0x80) {
      if (kept == limit - 1) break;
      ++kept;
    }
    ++end;
  }
  return text.substr(0, end) + "\xE2\x80\xA6";
}

// A linear or logarithmic map from an axis range onto pixels.
struct Scale {
  double low, high, pixel_low, pixel_high;
  bool logarithmic = false;
  double operator()(double value) const {
    const auto at = [&](double v) { return logarithmic ? std::log10(v) : v; };
    return pixel_low + (at(value) - at(low)) / (at(high) - at(low)) * (pixel_high - pixel_low);
  }
};

struct Frame {
  double left, top, width, height;
  double right() const { return left + width; }
  double bottom() const { return top + height; }
};

std::string marker(int kind, double x, double y, const std::string& colour) {
  const double r = 3.6;
  const std::string fill = fmt::format("fill=\"#{}\"", colour);
  const std::string ring = fmt::format("fill=\"#ffffff\" stroke=\"#{}\" stroke-width=\"1.5\"", colour);
  switch (kind) {
    case 0: return fmt::format("<circle cx=\"{}\" cy=\"{}\" r=\"{}\" {}/>", px(x), px(y), px(r), fill);
    case 1: return fmt::format("<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" {}/>", px(x - r * 0.9), px(y - r * 0.9),
                               px(r * 1.8), px(r * 1.8), fill);
    case 2: return fmt::format("<path d=\"M{},{} L{},{} L{},{} Z\" {}/>", px(x), px(y - r * 1.2), px(x + r * 1.1),
                               px(y + r * 0.8), px(x - r * 1.1), px(y + r * 0.8), fill);
    case 3: return fmt::format("<path d=\"M{},{} L{},{} L{},{} L{},{} Z\" {}/>", px(x), px(y - r * 1.3), px(x + r * 1.1),
                               px(y), px(x), px(y + r * 1.3), px(x - r * 1.1), px(y), fill);
    case 4: return fmt::format("<path d=\"M{},{} L{},{} L{},{} Z\" {}/>", px(x), px(y + r * 1.2), px(x + r * 1.1),
                               px(y - r * 0.8), px(x - r * 1.1), px(y - r * 0.8), fill);
    case 5: return fmt::format("<circle cx=\"{}\" cy=\"{}\" r=\"{}\" {}/>", px(x), px(y), px(r * 0.9), ring);
    case 6: return fmt::format("<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" {}/>", px(x - r * 0.8), px(y - r * 0.8),
                               px(r * 1.6), px(r * 1.6), ring);
    default: return fmt::format("<path d=\"M{},{} L{},{} M{},{} L{},{}\" fill=\"none\" stroke=\"#{}\" stroke-width=\"1.8\"/>",
                                px(x - r), px(y - r), px(x + r), px(y + r), px(x - r), px(y + r), px(x + r), px(y - r),
                                colour);
  }
}

// Hatching drawn in white over the series' colour, so bars differ in grey too.
std::string hatch_pattern(std::size_t index, const SeriesStyle& style) {
  static const std::array<const char*, figure_hatch_kinds> strokes = {
      "", "M-1,1 L1,-1 M0,6 L6,0 M5,7 L7,5", "M-1,5 L1,7 M0,0 L6,6 M5,-1 L7,1", "M0,3 L6,3", "M3,0 L3,6",
      "M0,3 L6,3 M3,0 L3,6", ""};
  const std::string drawing = style.hatch == figure_hatch_kinds - 1
                            ? std::string("<circle cx=\"3\" cy=\"3\" r=\"1.3\" fill=\"#ffffff\"/>")
                            : fmt::format("<path d=\"{}\" stroke=\"#ffffff\" stroke-width=\"1.3\" fill=\"none\"/>",
                                          strokes[style.hatch]);
  return fmt::format("<pattern id=\"hatch-{}\" patternUnits=\"userSpaceOnUse\" width=\"6\" height=\"6\">"
                     "<rect width=\"6\" height=\"6\" fill=\"#{}\"/>{}</pattern>\n",
                     index, style.colour, drawing);
}

std::string bar_fill(std::size_t index, const SeriesStyle& style) {
  return style.hatch == 0 ? fmt::format("#{}", style.colour) : fmt::format("url(#hatch-{})", index);
}

struct Range {
  double low = std::numeric_limits<double>::infinity();
  double high = -std::numeric_limits<double>::infinity();
  void add(double value) {
    if (!std::isfinite(value)) return;
    low = std::min(low, value);
    high = std::max(high, value);
  }
};

// The axis of `ticks` widened around its centre to `units` per pixel over `pixels`, with ticks at
// nice numbers of the new range.
AxisTicks widened(const AxisTicks& ticks, double units, double pixels) {
  const double centre = (ticks.low + ticks.high) / 2;
  const double low = centre - units * pixels / 2, high = centre + units * pixels / 2;
  return ticks_within(low, high, nice_ticks(low, high).step);
}

class SvgFigure {
 public:
  explicit SvgFigure(const Figure& figure) : figure_(figure) {
    for (std::size_t s = 0; s < figure.series.size(); ++s) {
      if (!figure.series[s].label.empty()) legend_.push_back(s);
    }
    lay_out();
  }

  std::string render() const {
    std::string out = "<?xml version=\"1.0\" encoding=\"UTF-8\" standalone=\"no\"?>\n";
    out += fmt::format("<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"{0}\" height=\"{1}\" "
                       "viewBox=\"0 0 {0} {1}\" font-family=\"DejaVu Sans, Liberation Sans, Arial, Helvetica, sans-serif\" "
                       "font-size=\"11\">\n",
                       page_width, height_);
    out += fmt::format("<title>{}</title>\n", xml_text(figure_.title.empty() ? figure_.name : figure_.title));
    if (!figure_.note.empty()) out += fmt::format("<desc>{}</desc>\n", xml_text(figure_.note));
    out += definitions();
    out += fmt::format("<rect width=\"{}\" height=\"{}\" fill=\"#ffffff\"/>\n", page_width, height_);
    out += headings();
    out += grid();
    out += fmt::format("<rect class=\"plot-area\" x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"none\" "
                       "stroke=\"#000000\" stroke-width=\"1\"/>\n",
                       px(frame_.left), px(frame_.top), px(frame_.width), px(frame_.height));
    out += x_axis();
    out += y_axis();
    if (figure_.draw_unit_circle) out += unit_circle();
    for (std::size_t s = 0; s < figure_.series.size(); ++s) out += series(s);
    out += legend();
    out += "</svg>\n";
    return out;
  }

 private:
  bool categorical() const { return !figure_.x_categories.empty(); }

  void lay_out() {
    Range x, y;
    const auto [x_low, x_high] = x_range(figure_);
    x.add(x_low);
    x.add(x_high);
    const auto [low, high] = value_range(figure_);
    y.add(low);
    y.add(high);
    if (figure_.kind == FigureKind::bars) y.add(0);
    if (figure_.draw_unit_circle) {
      for (const double bound : {-1.0, 1.0}) {
        x.add(bound);
        y.add(bound);
      }
    }
    const bool bars = figure_.kind == FigureKind::bars;
    const AxisTicks data_y = padded_value_axis(y.low, y.high, figure_.y_floor, figure_.y_ceiling,
                                               !(bars && y.low == 0), !(bars && y.high == 0));
    const AxisTicks data_x = categorical()     ? AxisTicks{}
                             : figure_.x_log ? padded_log_axis(x.low, x.high)
                                             : padded_value_axis(x.low, x.high, -HUGE_VAL, HUGE_VAL);
    x_ticks_ = data_x;
    y_ticks_ = data_y;

    std::size_t widest_legend = 0;
    for (const std::size_t s : legend_) {
      widest_legend = std::max(widest_legend, code_points(shortened(figure_.series[s].label, figure_legend_width)));
    }
    const double right_margin = legend_.empty() ? 20 : 56 + char_width * static_cast<double>(widest_legend);
    std::size_t widest_category = 0;
    for (const auto& category : figure_.x_categories) {
      widest_category = std::max(widest_category, code_points(shortened(category, figure_category_width)));
    }
    const double category_width = char_width * static_cast<double>(widest_category);
    const double first_category_width =
        categorical() ? char_width * static_cast<double>(code_points(shortened(figure_.x_categories[0], figure_category_width))) : 0;
    frame_.top = figure_.note.empty() ? 38 : 54;
    if (figure_.title.empty() && figure_.note.empty()) frame_.top = 16;
    frame_.width = page_width - 52 - right_margin;

    // The left margin holds the y tick labels (longer on an axis widened for equal units) and a
    // slanted first category label; the frame's width decides both: settle them in a few rounds.
    for (int round = 0; round < 3; ++round) {
      std::size_t widest_y_tick = 0;
      for (const double value : y_ticks_.values) {
        widest_y_tick = std::max(widest_y_tick, tick_label(value, y_ticks_.decimals).size());
      }
      double left = std::max(52.0, 34 + char_width * static_cast<double>(widest_y_tick));
      double bottom_margin = 46;
      if (categorical()) {
        const double band = frame_.width / static_cast<double>(figure_.x_categories.size());
        rotate_categories_ = category_width + 6 > band;
        if (rotate_categories_) {
          bottom_margin = 40 + category_width * 0.58;  // sine of the 35 degree slant
          left = std::max(left, 0.82 * first_category_width + 8 - band / 2);  // its cosine
        }
      }
      frame_.left = left;
      frame_.width = page_width - left - right_margin;
      height_ = std::max(min_page_height,
                         std::ceil(frame_.top + legend_row * static_cast<double>(legend_.size()) + 12 + bottom_margin));
      frame_.height = height_ - frame_.top - bottom_margin;
      if (figure_.equal_axes && !categorical() && !figure_.x_log) {
        const double units = std::max((data_x.high - data_x.low) / frame_.width, (data_y.high - data_y.low) / frame_.height);
        x_ticks_ = widened(data_x, units, frame_.width);
        y_ticks_ = widened(data_y, units, frame_.height);
      }
    }
    const double categories = static_cast<double>(figure_.x_categories.size());
    x_ = categorical() ? Scale{-0.5, categories - 0.5, frame_.left, frame_.right()}
                       : Scale{x_ticks_.low, x_ticks_.high, frame_.left, frame_.right(), figure_.x_log};
    y_ = Scale{y_ticks_.low, y_ticks_.high, frame_.bottom(), frame_.top};
  }

  std::string definitions() const {
    if (figure_.kind != FigureKind::bars) return "";
    std::string out = "<defs>\n";
    for (std::size_t s = 0; s < figure_.series.size(); ++s) {
      const SeriesStyle style = series_style(s);
      if (style.hatch != 0) out += hatch_pattern(s, style);
    }
    return out + "</defs>\n";
  }

  std::string headings() const {
    const double centre = page_width / 2;
    std::string out;
    // A long title, note or axis label gets smaller rather than cut: it must fit whole.
    const auto fitting_size = [](const std::string& text, double size, double room = page_width - 24) {
      return std::min(size, room / (0.6 * static_cast<double>(code_points(text))));
    };
    if (!figure_.title.empty()) {
      out += fmt::format("<text class=\"title\" x=\"{}\" y=\"22\" text-anchor=\"middle\" font-size=\"{}\" "
                         "font-weight=\"bold\">{}</text>\n",
                         px(centre), px(fitting_size(figure_.title, 15)), xml_text(figure_.title));
    }
    if (!figure_.note.empty()) {
      out += fmt::format("<text class=\"note\" x=\"{}\" y=\"{}\" text-anchor=\"middle\" font-size=\"{}\" "
                         "font-style=\"italic\" fill=\"#B00000\">{}</text>\n",
                         px(centre), figure_.title.empty() ? 22 : 40, px(fitting_size(figure_.note, 12)),
                         xml_text(figure_.note));
    }
    if (!figure_.x_label.empty()) {
      out += fmt::format("<text class=\"x-label\" x=\"{}\" y=\"{}\" text-anchor=\"middle\" font-size=\"{}\">{}</text>\n",
                         px(frame_.left + frame_.width / 2), px(height_ - 8), px(fitting_size(figure_.x_label, 12, frame_.width)),
                         xml_text(figure_.x_label));
    }
    if (!figure_.y_label.empty()) {
      const double y = frame_.top + frame_.height / 2;
      out += fmt::format("<text class=\"y-label\" x=\"16\" y=\"{0}\" transform=\"rotate(-90 16 {0})\" "
                         "text-anchor=\"middle\" font-size=\"{1}\">{2}</text>\n",
                         px(y), px(fitting_size(figure_.y_label, 12, frame_.height + 20)), xml_text(figure_.y_label));
    }
    return out;
  }

  std::string grid() const {
    std::string out = "<g class=\"grid\" stroke=\"#DDDDDD\" stroke-width=\"0.8\">\n";
    for (const double value : y_ticks_.values) {
      out += fmt::format("<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\"/>\n", px(frame_.left), px(y_(value)),
                         px(frame_.right()), px(y_(value)));
    }
    if (!categorical()) {
      for (const double value : x_ticks_.values) {
        out += fmt::format("<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\"/>\n", px(x_(value)), px(frame_.top),
                           px(x_(value)), px(frame_.bottom()));
      }
    }
    return out + "</g>\n";
  }

  std::string x_axis() const {
    std::string out = "<g class=\"x-axis\">\n";
    const double bottom = frame_.bottom();
    const auto tick = [&](double x, const std::string& label) {
      out += fmt::format("<line x1=\"{0}\" y1=\"{1}\" x2=\"{0}\" y2=\"{2}\" stroke=\"#000000\"/>\n", px(x), px(bottom),
                         px(bottom + 4));
      if (rotate_categories_) {
        out += fmt::format("<text x=\"{0}\" y=\"{1}\" transform=\"rotate(-35 {0} {1})\" text-anchor=\"end\">{2}</text>\n",
                           px(x + 3), px(bottom + 12), xml_text(label));
      } else {
        out += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{}</text>\n", px(x), px(bottom + 16),
                           xml_text(label));
      }
    };
    if (categorical()) {
      for (std::size_t c = 0; c < figure_.x_categories.size(); ++c) {
        tick(x_(static_cast<double>(c)), shortened(figure_.x_categories[c], figure_category_width));
      }
    } else {
      for (const double value : x_ticks_.values) tick(x_(value), tick_label(value, x_ticks_.decimals));
    }
    return out + "</g>\n";
  }

  std::string y_axis() const {
    std::string out = "<g class=\"y-axis\">\n";
    for (const double value : y_ticks_.values) {
      const double y = y_(value);
      out += fmt::format("<line x1=\"{0}\" y1=\"{1}\" x2=\"{2}\" y2=\"{1}\" stroke=\"#000000\"/>\n", px(frame_.left - 4),
                         px(y), px(frame_.left));
      out += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"end\">{}</text>\n", px(frame_.left - 6), px(y + 4),
                         tick_label(value, y_ticks_.decimals));
    }
    return out + "</g>\n";
  }

  std::string unit_circle() const {
    return fmt::format("<ellipse class=\"unit-circle\" cx=\"{}\" cy=\"{}\" rx=\"{}\" ry=\"{}\" fill=\"none\" "
                       "stroke=\"#888888\" stroke-width=\"1\" stroke-dasharray=\"4,3\"/>\n",
                       px(x_(0)), px(y_(0)), px(std::abs(x_(1) - x_(0))), px(std::abs(y_(1) - y_(0))));
  }

  std::string series(std::size_t index) const {
    const FigureSeries& series = figure_.series[index];
    const SeriesStyle style = series_style(index);
    std::string out = fmt::format("<g class=\"series\" id=\"series-{}\">\n", index);
    const auto finite = [&](std::size_t i) { return std::isfinite(series.x[i]) && std::isfinite(series.y[i]); };
    if (figure_.kind == FigureKind::bars) {
      const double band = x_(1) - x_(0);
      const double group = 0.8 * band;
      const double width = group / static_cast<double>(figure_.series.size());
      const double zero = y_(0);
      for (std::size_t i = 0; i < series.x.size(); ++i) {
        if (!finite(i)) continue;
        const double left = x_(series.x[i]) - group / 2 + width * static_cast<double>(index);
        const double top = std::min(zero, y_(series.y[i]));
        out += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"{}\" stroke=\"#333333\" "
                           "stroke-width=\"0.6\"/>\n",
                           px(left), px(top), px(width), px(std::abs(zero - y_(series.y[i]))), bar_fill(index, style));
        out += whisker(series, i, left + width / 2, "333333");
      }
      return out + "</g>\n";
    }
    if (figure_.kind == FigureKind::lines) {
      // One path per run of finite points: a gap breaks the line.
      std::string path;
      std::size_t run = 0;
      const auto close_run = [&]() {
        if (run >= 2) {
          out += fmt::format("<path d=\"{}\" fill=\"none\" stroke=\"#{}\" stroke-width=\"1.8\" stroke-linejoin=\"round\"{}/>\n",
                             path, style.colour,
                             style.dash == 0 ? "" : fmt::format(" stroke-dasharray=\"{}\"", svg_dashes[style.dash]));
        }
        path.clear();
        run = 0;
      };
      for (std::size_t i = 0; i < series.x.size(); ++i) {
        if (!finite(i)) {
          close_run();
          continue;
        }
        path += fmt::format("{}{},{}", run == 0 ? "M" : " L", px(x_(series.x[i])), px(y_(series.y[i])));
        ++run;
      }
      close_run();
    }
    for (std::size_t i = 0; i < series.x.size(); ++i) {
      if (!finite(i)) continue;
      out += whisker(series, i, x_(series.x[i]), style.colour);
      out += marker(style.marker, x_(series.x[i]), y_(series.y[i]), style.colour);
    }
    return out + "</g>\n";
  }

  // Point i's spread over seeds as a capped vertical line at pixel x; nothing where it has none.
  std::string whisker(const FigureSeries& series, std::size_t i, double x, const std::string& colour) const {
    const auto [bottom, top] = whisker_ends(figure_, series, i);
    if (!std::isfinite(bottom) || !std::isfinite(top)) return "";
    const double cap = 3;
    return fmt::format("<path class=\"spread\" d=\"M{0},{1} L{0},{2} M{3},{1} L{4},{1} M{3},{2} L{4},{2}\" fill=\"none\" "
                       "stroke=\"#{5}\" stroke-width=\"1\"/>\n",
                       px(x), px(y_(bottom)), px(y_(top)), px(x - cap), px(x + cap), colour);
  }

  std::string legend() const {
    if (legend_.empty()) return "";
    std::string out = "<g class=\"legend\">\n";
    const double left = frame_.right() + 12;
    for (std::size_t row = 0; row < legend_.size(); ++row) {
      const std::size_t index = legend_[row];
      const SeriesStyle style = series_style(index);
      const double y = frame_.top + 10 + legend_row * static_cast<double>(row);
      if (figure_.kind == FigureKind::bars) {
        out += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"16\" height=\"11\" fill=\"{}\" stroke=\"#333333\" "
                           "stroke-width=\"0.6\"/>\n",
                           px(left + 4), px(y - 5.5), bar_fill(index, style));
      } else {
        if (figure_.kind == FigureKind::lines) {
          out += fmt::format("<line x1=\"{0}\" y1=\"{1}\" x2=\"{2}\" y2=\"{1}\" stroke=\"#{3}\" stroke-width=\"1.8\"{4}/>\n",
                             px(left), px(y), px(left + 24), style.colour,
                             style.dash == 0 ? "" : fmt::format(" stroke-dasharray=\"{}\"", svg_dashes[style.dash]));
        }
        out += marker(style.marker, left + 12, y, style.colour);
      }
      out += fmt::format("<text x=\"{}\" y=\"{}\">{}</text>\n", px(left + 30), px(y + 4),
                         xml_text(shortened(figure_.series[index].label, figure_legend_width)));
    }
    return out + "</g>\n";
  }

  const Figure& figure_;
  std::vector<std::size_t> legend_;  // series with a label, in order
  AxisTicks x_ticks_, y_ticks_;
  Frame frame_{};
  double height_ = min_page_height;
  bool rotate_categories_ = false;
  Scale x_{}, y_{};
};

}  // namespace

std::string render_svg(const Figure& figure) {
  require_valid_figure(figure);
  return SvgFigure(figure).render();
}

}  // namespace fscil
