#include "reports/figure.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>

#include "core/atomic_file.h"
#include "reports/axis_ticks.h"
#include "reports/csv_fields.h"
#include "reports/figure_csv.h"
#include "reports/figure_style.h"
#include "reports/figure_writer.h"
#include "reports/pgfplots_figure.h"
#include "core/error.h"
#include "reports/svg_figure.h"
#include "core/text_file.h"
#include "tests/reports/markup_checks.h"
#include "tests/temporary_directory.h"

namespace fscil {
namespace {

constexpr double gap = std::numeric_limits<double>::quiet_NaN();
constexpr double pixel = 0.006;  // coordinates are written with two decimals

Figure lines_figure(std::vector<double> x, std::vector<double> y) {
  Figure figure;
  figure.name = "accuracy";
  figure.title = "Accuracy per session";
  figure.x_label = "session";
  figure.y_label = "accuracy (%)";
  figure.kind = FigureKind::lines;
  figure.series = {{"prototype", std::move(x), std::move(y)}};
  return figure;
}

struct Box {
  double left, top, width, height;
  double right() const { return left + width; }
  double bottom() const { return top + height; }
};

Box plot_area(const std::string& svg) {
  const auto rects = tags_of(svg, "rect");
  for (const auto& rect : rects) {
    if (rect.find("class=\"plot-area\"") != std::string::npos) {
      return {number_attribute(rect, "x"), number_attribute(rect, "y"), number_attribute(rect, "width"),
              number_attribute(rect, "height")};
    }
  }
  ADD_FAILURE() << "no plot area in the SVG";
  return {0, 0, 0, 0};
}

// The tags of element `name` drawn for series `index`.
std::vector<std::string> series_tags(const std::string& svg, std::size_t index, const std::string& name) {
  const std::size_t begin = svg.find("id=\"series-" + std::to_string(index) + "\"");
  if (begin == std::string::npos) return {};
  return tags_of(svg, name, begin, svg.find("</g>", begin));
}

// Issue 70: points at the ends of the range sat on the frame (prototype's 60 on the top border),
// and the R axis ran -1 to 1 where R cannot be negative.
TEST(FigureTicks, AValueAxisIsPaddedAndNeverTicksPastTheQuantitysBounds) {
  const AxisTicks novel = padded_value_axis(0, 60, 0, 100);
  EXPECT_DOUBLE_EQ(novel.values.front(), 0);
  EXPECT_DOUBLE_EQ(novel.values.back(), 60);
  EXPECT_DOUBLE_EQ(novel.low, -2.4);  // 4% of the ticks' 0 to 60 past each end
  EXPECT_DOUBLE_EQ(novel.high, 62.4);

  const AxisTicks near_full = padded_value_axis(96.5, 100, 0, 100);
  EXPECT_LE(near_full.values.back(), 100) << "no tick above 100%";
  EXPECT_GT(near_full.high, 100) << "100% off the frame";

  const AxisTicks ratio = padded_value_axis(0, 0, 0, HUGE_VAL);  // R is 0 in every session
  EXPECT_DOUBLE_EQ(ratio.values.front(), 0) << "no negative R";
  EXPECT_GT(ratio.values.back(), 0);
  EXPECT_LT(ratio.low, 0);

  const AxisTicks bars = padded_value_axis(0, 50, 0, HUGE_VAL, false, true);
  EXPECT_DOUBLE_EQ(bars.low, 0) << "a bar chart's baseline takes no padding";
  EXPECT_DOUBLE_EQ(bars.high, 52);

  const AxisTicks drop = padded_value_axis(-12, 30, 0, 100);  // data past a bound keep their ticks
  EXPECT_LT(drop.values.front(), -12 + 1e-9);
}

// Issue 70: N_ps 5 to 1000 was spaced as six equal categories.
TEST(FigureTicks, ALogarithmicAxisTicksPowersOfTenOrOneTwoFiveAndReachesPastTheData) {
  const AxisTicks probes = padded_log_axis(5, 1000);
  EXPECT_EQ(probes.values, (std::vector<double>{10, 100, 1000}));
  // 4% of the 2.3 decades past each end.
  EXPECT_NEAR(std::log10(probes.low), std::log10(5) - 0.04 * std::log10(200), 1e-12);
  EXPECT_NEAR(std::log10(probes.high), 3 + 0.04 * std::log10(200), 1e-12);
  EXPECT_DOUBLE_EQ(probes.step, 10);
  EXPECT_EQ(probes.decimals, 0);

  const AxisTicks short_axis = padded_log_axis(2, 8);  // under a decade: 1, 2 and 5 times powers of ten
  EXPECT_EQ(short_axis.values, (std::vector<double>{2, 5}));
  const AxisTicks small = padded_log_axis(0.001, 0.1);
  EXPECT_EQ(small.decimals, 3);
  EXPECT_EQ(tick_label(small.values.front(), small.decimals), "0.001");
  const AxisTicks nothing = padded_log_axis(gap, gap);
  EXPECT_LT(nothing.low, 1);
  EXPECT_GT(nothing.high, 10);
}

TEST(FigureTicks, FallOnNiceNumbersCoveringTheData) {
  const AxisTicks percent = nice_ticks(0, 100);
  EXPECT_DOUBLE_EQ(percent.step, 20);
  EXPECT_EQ(percent.values, (std::vector<double>{0, 20, 40, 60, 80, 100}));
  EXPECT_EQ(percent.decimals, 0);

  const AxisTicks accuracies = nice_ticks(43.2, 91.7);
  EXPECT_DOUBLE_EQ(accuracies.low, 40);
  EXPECT_DOUBLE_EQ(accuracies.high, 100);
  EXPECT_DOUBLE_EQ(accuracies.step, 10);

  const AxisTicks small = nice_ticks(0.012, 0.049);
  EXPECT_DOUBLE_EQ(small.step, 0.01);
  EXPECT_DOUBLE_EQ(small.low, 0.01);
  EXPECT_DOUBLE_EQ(small.high, 0.05);
  EXPECT_EQ(small.decimals, 2);
  EXPECT_EQ(tick_label(small.values[2], small.decimals), "0.03");  // not 0.030000000000000002

  const AxisTicks one_value = nice_ticks(5, 5);
  EXPECT_LT(one_value.low, 5);
  EXPECT_GT(one_value.high, 5);
  const AxisTicks no_data = nice_ticks(gap, gap);
  EXPECT_DOUBLE_EQ(no_data.low, 0);
  EXPECT_DOUBLE_EQ(no_data.high, 1);

  EXPECT_EQ(tick_label(-1e-17, 1), "0.0");
  EXPECT_EQ(tick_label(-0.5, 1), "-0.5");
  EXPECT_EQ(ticks_within(-1.3, 1.3, 0.5).values, (std::vector<double>{-1, -0.5, 0, 0.5, 1}));
}

TEST(FigureSvg, IsAWellFormedSelfContainedSvgDocument) {
  for (const FigureKind kind : {FigureKind::lines, FigureKind::bars, FigureKind::scatter}) {
    Figure figure = lines_figure({0, 1, 2}, {50, 60, 55});
    figure.kind = kind;
    figure.x_categories = {"base", "s1", "s2"};
    figure.note = "selected on test (inflated)";
    figure.series.push_back({"cop-fscil", {0, 1, 2}, {52, gap, 58}});
    const std::string svg = render_svg(figure);
    SCOPED_TRACE(svg);
    EXPECT_EQ(markup_problem(svg), "");
    EXPECT_EQ(svg.rfind("<?xml version=\"1.0\" encoding=\"UTF-8\"", 0), 0u);
    EXPECT_NE(svg.find("<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"640\" height=\"400\" "
                       "viewBox=\"0 0 640 400\""),
              std::string::npos);
    EXPECT_NE(svg.find("<title>Accuracy per session</title>"), std::string::npos);
    EXPECT_NE(svg.find("<desc>selected on test (inflated)</desc>"), std::string::npos);
    EXPECT_NE(svg.find("class=\"note\""), std::string::npos);
    EXPECT_NE(svg.find(">selected on test (inflated)</text>"), std::string::npos);
    EXPECT_NE(svg.find(">cop-fscil</text>"), std::string::npos);  // legend
    EXPECT_NE(svg.find(">accuracy (%)</text>"), std::string::npos);
    EXPECT_NE(svg.find(">s2</text>"), std::string::npos);  // a category
    for (const char* outside : {"<script", "href", "@import", "url(http", "<image", "<foreignObject"}) {
      EXPECT_EQ(svg.find(outside), std::string::npos) << outside;
    }
  }
}

TEST(FigureSvg, EscapesEveryText) {
  Figure figure = lines_figure({0, 1}, {1, 2});
  figure.title = "Acc < 100 & \"best\" 'x'";
  figure.x_label = "a>b";
  figure.series[0].label = "m<1>&";
  figure.note = "bad \xFF byte and \x01 control";
  const std::string svg = render_svg(figure);
  EXPECT_EQ(markup_problem(svg), "");
  EXPECT_NE(svg.find(">Acc &lt; 100 &amp; &quot;best&quot; &#39;x&#39;</text>"), std::string::npos);
  EXPECT_NE(svg.find(">a&gt;b</text>"), std::string::npos);
  EXPECT_NE(svg.find(">m&lt;1&gt;&amp;</text>"), std::string::npos);
  EXPECT_NE(svg.find("bad \xEF\xBF\xBD byte and \xEF\xBF\xBD control"), std::string::npos);
  EXPECT_EQ(svg.find('\xFF'), std::string::npos);
  EXPECT_EQ(svg.find('\x01'), std::string::npos);
}

// Where `value` falls along an axis whose ticks run from `low` to `high`, as a fraction of the
// axis: it runs 4% of the ticks' span past them each way (padded_value_axis).
double along(double value, double low, double high) {
  const double pad = 0.04 * (high - low);
  return (value - (low - pad)) / (high - low + 2 * pad);
}

TEST(FigureSvg, PlacesEachPointWhereItsAxesSayItIs) {
  const std::string svg = render_svg(lines_figure({0, 5, 10}, {0, 50, 100}));
  const Box area = plot_area(svg);
  ASSERT_GT(area.width, 300);
  ASSERT_GT(area.height, 250);
  const auto points = series_tags(svg, 0, "circle");
  ASSERT_EQ(points.size(), 3u);
  // Ticks run 0 to 10 and 0 to 100, the axes 4% of that further each way: the first point near
  // the lower left corner but off the frame, the last near the upper right.
  EXPECT_NEAR(number_attribute(points[0], "cx"), area.left + area.width * along(0, 0, 10), pixel);
  EXPECT_NEAR(number_attribute(points[0], "cy"), area.bottom() - area.height * along(0, 0, 100), pixel);
  EXPECT_GT(number_attribute(points[0], "cx"), area.left + 10);
  EXPECT_NEAR(number_attribute(points[1], "cx"), area.left + area.width / 2, pixel);
  EXPECT_NEAR(number_attribute(points[1], "cy"), area.top + area.height / 2, pixel);
  EXPECT_NEAR(number_attribute(points[2], "cx"), area.left + area.width * along(10, 0, 10), pixel);
  EXPECT_NEAR(number_attribute(points[2], "cy"), area.bottom() - area.height * along(100, 0, 100), pixel);
  EXPECT_GT(number_attribute(points[2], "cy"), area.top + 10);
  for (const char* label : {">0</text>", ">20</text>", ">80</text>", ">100</text>", ">10</text>"}) {
    EXPECT_NE(svg.find(label), std::string::npos) << label;
  }

  // 43.2 to 91.7 gets the ticks 40 to 100.
  const std::string accuracies = render_svg(lines_figure({0, 1}, {43.2, 91.7}));
  const Box box = plot_area(accuracies);
  const auto marks = series_tags(accuracies, 0, "circle");
  ASSERT_EQ(marks.size(), 2u);
  EXPECT_NEAR(number_attribute(marks[1], "cy"), box.bottom() - box.height * along(91.7, 40, 100), pixel);
  EXPECT_NEAR(number_attribute(marks[0], "cy"), box.bottom() - box.height * along(43.2, 40, 100), pixel);
  EXPECT_NE(accuracies.find(">40</text>"), std::string::npos);
  EXPECT_EQ(accuracies.find(">30</text>"), std::string::npos);
}

TEST(FigureSvg, ALogarithmicAxisSpacesEachDecadeEqually) {
  Figure figure = lines_figure({5, 10, 100, 1000}, {70, 71, 72, 73});
  figure.x_log = true;
  const std::string svg = render_svg(figure);
  const auto points = series_tags(svg, 0, "circle");
  ASSERT_EQ(points.size(), 4u);
  const double ten = number_attribute(points[1], "cx"), hundred = number_attribute(points[2], "cx"),
               thousand = number_attribute(points[3], "cx");
  EXPECT_NEAR(hundred - ten, thousand - hundred, 2 * pixel);
  EXPECT_NEAR(ten - number_attribute(points[0], "cx"), (hundred - ten) * std::log10(2), 2 * pixel);
  const Box area = plot_area(svg);
  EXPECT_GT(number_attribute(points[0], "cx"), area.left + 5) << "the first point off the frame";
  EXPECT_LT(thousand, area.right() - 5);
  for (const char* label : {">10</text>", ">100</text>", ">1000</text>"}) {
    EXPECT_NE(svg.find(label), std::string::npos) << label;
  }
}

// Issue 70: figures plotted means only, however far apart the seeds were.
TEST(FigureSvg, WhiskersSpanOneSpreadEachWayAndStopAtTheQuantitysBounds) {
  Figure figure = lines_figure({0, 1, 2}, {50, 97, 70});
  figure.y_floor = 0;
  figure.y_ceiling = 100;
  figure.series[0].y_spread = {10, 6, gap};  // the last point has one seed
  const std::string svg = render_svg(figure);
  const auto whiskers = series_tags(svg, 0, "path");
  std::vector<std::string> spreads;
  for (const auto& path : whiskers) {
    if (path.find("class=\"spread\"") != std::string::npos) spreads.push_back(path);
  }
  ASSERT_EQ(spreads.size(), 2u) << svg;
  const Box area = plot_area(svg);
  // The axis covers 40 to 100 (60 + 40, 97 + 6 cut at 100), padded 4% each way.
  const auto y_of = [&](double value) { return area.bottom() - area.height * along(value, 40, 100); };
  EXPECT_NE(spreads[0].find(fmt::format("L{:.2f},{:.2f}", area.left + area.width * along(0, 0, 2), y_of(60))),
            std::string::npos) << spreads[0];
  EXPECT_NE(spreads[0].find(fmt::format(",{:.2f} L", y_of(40))), std::string::npos) << spreads[0];
  EXPECT_NE(spreads[1].find(fmt::format(",{:.2f}", y_of(100))), std::string::npos) << "cut at 100: " << spreads[1];
  EXPECT_EQ(spreads[1].find(fmt::format(",{:.2f}", y_of(103))), std::string::npos) << spreads[1];

  Figure bars = figure;
  bars.kind = FigureKind::bars;
  bars.x_categories = {"a", "b", "c"};
  EXPECT_EQ(occurrences(render_svg(bars), "class=\"spread\""), 2u);
  EXPECT_EQ(occurrences(render_svg(lines_figure({0, 1}, {1, 2})), "class=\"spread\""), 0u);
}

TEST(FigureSvg, ANonFiniteValueIsAGapInTheLine) {
  const std::string svg = render_svg(lines_figure({0, 1, 2, 3}, {10, gap, 30, 40}));
  EXPECT_EQ(series_tags(svg, 0, "circle").size(), 3u);
  const auto paths = series_tags(svg, 0, "path");
  ASSERT_EQ(paths.size(), 1u);  // 0 alone draws no line; 2 to 3 is one segment
  EXPECT_EQ(occurrences(paths[0], " L"), 1u);
  const Box area = plot_area(svg);
  // The segment runs from (2, 30) to (3, 40) on the axes of ticks 0 to 3 and 10 to 40.
  EXPECT_NE(paths[0].find(fmt::format("M{:.2f},", area.left + area.width * along(2, 0, 3))), std::string::npos) << paths[0];

  const std::string infinite = render_svg(lines_figure({0, 1, 2}, {1, std::numeric_limits<double>::infinity(), 3}));
  EXPECT_EQ(series_tags(infinite, 0, "circle").size(), 2u);
  EXPECT_TRUE(series_tags(infinite, 0, "path").empty());

  const std::string nothing = render_svg(lines_figure({0, 1}, {gap, gap}));
  EXPECT_EQ(markup_problem(nothing), "");
  EXPECT_TRUE(series_tags(nothing, 0, "circle").empty());
  EXPECT_NE(nothing.find(">1.0</text>"), std::string::npos);  // the empty axis 0 to 1
}

TEST(FigureSvg, BarsStandSideBySidePerCategoryAndSkipGaps) {
  Figure figure;
  figure.name = "costs";
  figure.kind = FigureKind::bars;
  figure.x_categories = {"prototype", "pits-sc", "orco"};
  figure.series = {{"base", {0, 1, 2}, {10, 50, 30}}, {"update", {0, 1, 2}, {20, gap, 40}}};
  const std::string svg = render_svg(figure);
  EXPECT_EQ(markup_problem(svg), "");
  const auto first = series_tags(svg, 0, "rect"), second = series_tags(svg, 1, "rect");
  ASSERT_EQ(first.size(), 3u);
  ASSERT_EQ(second.size(), 2u);  // the gap draws no bar
  const Box area = plot_area(svg);
  const double band = area.width / 3;
  // Axis 0 to 50; each category's group is 80% of its band, split between the two series.
  EXPECT_NEAR(number_attribute(first[0], "x"), area.left + 0.1 * band, pixel);
  EXPECT_NEAR(number_attribute(first[0], "width"), 0.4 * band, pixel);
  EXPECT_NEAR(number_attribute(second[0], "x"), area.left + 0.5 * band, pixel);
  // Ticks 0 to 50, the axis to 52 above and none below the bars' baseline.
  EXPECT_NEAR(number_attribute(first[0], "height"), area.height * 10 / 52, pixel);
  EXPECT_NEAR(number_attribute(first[0], "y") + number_attribute(first[0], "height"), area.bottom(), pixel);
  EXPECT_NEAR(number_attribute(first[1], "y"), area.top + area.height * 2 / 52, pixel);  // 50 stops short of the top
  EXPECT_NEAR(number_attribute(second[1], "x"), area.left + 2.5 * band, pixel);  // orco's, category 2
  // The second series is hatched, so the two differ in grey too.
  EXPECT_NE(second[0].find("fill=\"url(#hatch-1)\""), std::string::npos);
  EXPECT_NE(svg.find("<pattern id=\"hatch-1\""), std::string::npos);
  EXPECT_NE(svg.find(">pits-sc</text>"), std::string::npos);
}

TEST(FigureSvg, ScatterOnTheUnitCircleKeepsOneUnitEqualOnBothAxes) {
  Figure figure;
  figure.name = "prototypes";
  figure.kind = FigureKind::scatter;
  figure.equal_axes = true;
  figure.draw_unit_circle = true;
  figure.series = {{"classes", {1, 0, -0.5}, {0, 1, -0.5}}};
  const std::string svg = render_svg(figure);
  EXPECT_EQ(markup_problem(svg), "");
  const auto circle = tags_of(svg, "ellipse");
  ASSERT_EQ(circle.size(), 1u);
  const double cx = number_attribute(circle[0], "cx"), cy = number_attribute(circle[0], "cy");
  const double rx = number_attribute(circle[0], "rx"), ry = number_attribute(circle[0], "ry");
  EXPECT_NEAR(rx, ry, 2 * pixel);
  EXPECT_GT(rx, 50);
  const auto points = series_tags(svg, 0, "circle");
  ASSERT_EQ(points.size(), 3u);
  EXPECT_TRUE(series_tags(svg, 0, "path").empty());  // points only
  EXPECT_NEAR(number_attribute(points[0], "cx"), cx + rx, 2 * pixel);
  EXPECT_NEAR(number_attribute(points[0], "cy"), cy, 2 * pixel);
  EXPECT_NEAR(number_attribute(points[1], "cx"), cx, 2 * pixel);
  EXPECT_NEAR(number_attribute(points[1], "cy"), cy - ry, 2 * pixel);

  // Data four times wider than high still gets square units.
  Figure wide = figure;
  wide.draw_unit_circle = false;
  wide.series = {{"", {0, 4}, {0, 1}}};
  const auto marks = series_tags(render_svg(wide), 0, "circle");
  ASSERT_EQ(marks.size(), 2u);
  const double per_x = (number_attribute(marks[1], "cx") - number_attribute(marks[0], "cx")) / 4;
  const double per_y = number_attribute(marks[0], "cy") - number_attribute(marks[1], "cy");
  EXPECT_NEAR(per_x, per_y, 0.02);
}

TEST(FigureSvg, SeriesDifferInColourAndInGrey) {
  std::set<std::string> colours;
  std::set<std::pair<int, int>> dash_and_marker;
  for (std::size_t s = 0; s < 40; ++s) {
    const SeriesStyle style = series_style(s);
    if (s < figure_palette.size()) colours.insert(style.colour);
    dash_and_marker.insert({style.dash, style.marker});
  }
  EXPECT_GE(colours.size(), 13u) << "the thirteen methods of --methods all, each its own colour";
  EXPECT_EQ(dash_and_marker.size(), 40u);
  // Readable on white paper: relative luminance (sRGB) well below white's 1 (yellow F0E442 is 0.78).
  const auto linear = [](const char* colour, int offset) {
    const double value = std::stoi(std::string(colour + offset, 2), nullptr, 16) / 255.0;
    return value <= 0.04045 ? value / 12.92 : std::pow((value + 0.055) / 1.055, 2.4);
  };
  for (const char* colour : figure_palette) {
    EXPECT_LT(0.2126 * linear(colour, 0) + 0.7152 * linear(colour, 2) + 0.0722 * linear(colour, 4), 0.5) << colour;
  }
  // Told apart: every two at least 25 CIELAB units apart (D65; Okabe and Ito's closest pair, blue and sky blue, is 26).
  const auto lab = [&](const char* colour) {
    const double r = linear(colour, 0), g = linear(colour, 2), b = linear(colour, 4);
    const auto f = [](double t) { return t > 0.008856 ? std::cbrt(t) : 7.787 * t + 16.0 / 116; };
    const double fx = f((0.4124 * r + 0.3576 * g + 0.1805 * b) / 0.9505), fy = f(0.2126 * r + 0.7152 * g + 0.0722 * b),
                 fz = f((0.0193 * r + 0.1192 * g + 0.9505 * b) / 1.089);
    return std::array<double, 3>{116 * fy - 16, 500 * (fx - fy), 200 * (fy - fz)};
  };
  for (std::size_t i = 0; i < figure_palette.size(); ++i) {
    for (std::size_t j = i + 1; j < figure_palette.size(); ++j) {
      const auto a = lab(figure_palette[i]), c = lab(figure_palette[j]);
      EXPECT_GE(std::hypot(a[0] - c[0], a[1] - c[1], a[2] - c[2]), 25) << figure_palette[i] << " " << figure_palette[j];
    }
  }
  Figure many = lines_figure({0, 1}, {1, 2});
  for (int s = 1; s < 8; ++s) many.series.push_back({"m" + std::to_string(s), {0, 1}, {1.0 + s, 2.0 + s}});
  const std::string svg = render_svg(many);
  EXPECT_EQ(markup_problem(svg), "");
  EXPECT_NE(series_tags(svg, 1, "path")[0].find("stroke-dasharray=\"7,3\""), std::string::npos);
  EXPECT_EQ(series_tags(svg, 1, "rect").size(), 2u);  // squares
}

TEST(FigureSvg, RefusesAFigureItCannotRender) {
  const auto refused = [](const Figure& figure) {
    EXPECT_THROW(render_svg(figure), ReportError);
    EXPECT_THROW(render_pgfplots(figure), ReportError);
    EXPECT_THROW(render_figure_csv(figure), ReportError);
  };
  Figure figure = lines_figure({0, 1}, {1, 2});
  for (const char* name : {"", "Accuracy", "a/b", "../up", "a b"}) {
    figure.name = name;
    refused(figure);
  }
  figure = lines_figure({0, 1, 2}, {1, 2});
  refused(figure);
  figure = lines_figure({0, 3}, {1, 2});
  figure.x_categories = {"a", "b", "c"};
  refused(figure);  // 3 is not a category
  figure.series[0].x = {0, 0.5};
  refused(figure);
  figure.series[0].x = {0, 2};
  EXPECT_NO_THROW(render_svg(figure));
  Figure bars = lines_figure({0, 1}, {1, 2});
  bars.kind = FigureKind::bars;
  refused(bars);
  Figure spread = lines_figure({0, 1}, {1, 2});
  spread.series[0].y_spread = {1};
  refused(spread);  // one spread for two points
  spread.series[0].y_spread = {1, -1};
  refused(spread);
  spread.series[0].y_spread = {1, gap};
  EXPECT_NO_THROW(render_svg(spread));
  Figure logarithmic = lines_figure({0, 10}, {1, 2});
  logarithmic.x_log = true;
  refused(logarithmic);  // 0 has no logarithm
  logarithmic.series[0].x = {1, 10};
  EXPECT_NO_THROW(render_svg(logarithmic));
  logarithmic.x_categories = {"a", "b", "c", "d", "e", "f", "g", "h", "i", "j", "k"};
  refused(logarithmic);
  figure.name = "Bad";
  std::string message;
  try {
    render_svg(figure);
  } catch (const ReportError& error) {
    message = error.what();
  }
  EXPECT_NE(message.find("figure name 'Bad' is not a file stem"), std::string::npos) << message;
}

// Braces not escaped as \{ or \}: never more closing than opening, and as many of each.
bool braces_balance(const std::string& tex) {
  int depth = 0;
  for (std::size_t i = 0; i < tex.size(); ++i) {
    if (tex[i] == '\\') {
      ++i;
    } else if (tex[i] == '{') {
      ++depth;
    } else if (tex[i] == '}' && --depth < 0) {
      return false;
    }
  }
  return depth == 0;
}

TEST(FigurePgfplots, HoldsCoordinatesLegendAndEscapedLabels) {
  Figure figure = lines_figure({0, 1, 2}, {91.2, gap, 79.875});
  figure.title = "Accuracy 100% on set_a {b} ~ \\x";
  figure.series.push_back({"cop-fscil & co", {0, 1, 2}, {92, 86.1, 82.4}});
  figure.note = "selected on test (inflated)";
  const std::string tex = render_pgfplots(figure);
  SCOPED_TRACE(tex);
  EXPECT_EQ(tex.rfind("% fscil-bench figure accuracy: ", 0), 0u);
  EXPECT_NE(tex.find("\\usepackage{pgfplots}"), std::string::npos);
  EXPECT_NE(tex.find("% Note: selected on test (inflated)\n"), std::string::npos);
  EXPECT_TRUE(braces_balance(tex));
  EXPECT_EQ(occurrences(tex, "\\begin{tikzpicture}"), 1u);
  EXPECT_EQ(occurrences(tex, "\\end{tikzpicture}"), 1u);
  EXPECT_NE(tex.find("\\begin{axis}["), std::string::npos);
  EXPECT_NE(tex.find("title={Accuracy 100\\% on set\\_a \\{b\\} \\textasciitilde{} \\textbackslash{}x\\\\"
                     "{\\footnotesize\\itshape selected on test (inflated)}}"),
            std::string::npos);
  EXPECT_NE(tex.find("xlabel={session}"), std::string::npos);
  EXPECT_NE(tex.find("ylabel={accuracy (\\%)}"), std::string::npos);
  EXPECT_NE(tex.find("unbounded coords=jump"), std::string::npos);
  // A gap stays in a line as nan, where the line breaks.
  EXPECT_NE(tex.find("coordinates {(0,91.2) (1,nan) (2,79.875)};"), std::string::npos);
  EXPECT_NE(tex.find("coordinates {(0,92) (1,86.1) (2,82.4)};"), std::string::npos);
  EXPECT_NE(tex.find("\\addlegendentry{prototype}"), std::string::npos);
  EXPECT_NE(tex.find("\\addlegendentry{cop-fscil \\& co}"), std::string::npos);
  // The colours of render_svg's first two series, dashed second line with solid marks.
  EXPECT_NE(tex.find("\\definecolor{fscilfigure0}{HTML}{0072B2}"), std::string::npos);
  EXPECT_NE(tex.find("\\definecolor{fscilfigure1}{HTML}{D55E00}"), std::string::npos);
  EXPECT_NE(tex.find("\\addplot[color=fscilfigure1, dashed, thick, mark=square*, mark options={solid}]"),
            std::string::npos);
  EXPECT_EQ(tex.find("xmin="), std::string::npos);
  EXPECT_EQ(tex.find("ybar"), std::string::npos);
}

TEST(FigurePgfplots, BarsAreYbarOverTheNamedCategories) {
  Figure figure;
  figure.name = "costs";
  figure.kind = FigureKind::bars;
  figure.y_label = "seconds";
  figure.x_categories = {"prototype", "cop-fscil/cpi+pspc", "my_method"};
  figure.series = {{"base", {0, 1, 2}, {41.5, 52, 80.25}}, {"update", {0, 1, 2}, {0.4, gap, 9.8}}};
  const std::string tex = render_pgfplots(figure);
  SCOPED_TRACE(tex);
  EXPECT_TRUE(braces_balance(tex));
  EXPECT_NE(tex.find("xtick={0,1,2}, xticklabels={{prototype},{cop-fscil/cpi+pspc},{my\\_method}}, xmin=-0.5, xmax=2.5"),
            std::string::npos);
  // 80% of each category's share of the 7 cm axis, split between two series.
  EXPECT_NE(tex.find("ybar=0pt, bar width=0.933cm"), std::string::npos);
  EXPECT_NE(tex.find("ymin=0"), std::string::npos);
  EXPECT_NE(tex.find("\\addplot[fill=fscilfigure0, draw=black] coordinates {(0,41.5) (1,52) (2,80.25)};"),
            std::string::npos);
  EXPECT_NE(tex.find("coordinates {(0,0.4) (2,9.8)};"), std::string::npos);  // no bar for the gap

  figure.series[1].y[0] = -3;
  EXPECT_EQ(render_pgfplots(figure).find("ymin=0"), std::string::npos);  // a negative bar needs the axis below 0
}

TEST(FigurePgfplots, SpreadsAreErrorBarsAndALogarithmicAxisIsXmodeLog) {
  Figure figure = lines_figure({5, 50, 1000}, {70, 97, 80});
  figure.y_ceiling = 100;
  figure.x_log = true;
  figure.series[0].y_spread = {2.5, 6, gap};
  figure.series.push_back({"orco", {5, 1000}, {60, 61}});
  const std::string tex = render_pgfplots(figure);
  SCOPED_TRACE(tex);
  EXPECT_TRUE(braces_balance(tex));
  EXPECT_NE(tex.find("xmode=log, log basis x=10, log ticks with fixed point, xmin="), std::string::npos);
  EXPECT_NE(tex.find("xtick={10,100,1000}"), std::string::npos);
  EXPECT_NE(tex.find("error bars/.cd, y dir=both, y explicit, error bar style={solid, thin, fscilfigure0}]"),
            std::string::npos);
  // 97 + 6 stops at 100; the point with one seed gets none.
  EXPECT_NE(tex.find("coordinates {(5,70) += (0,2.5) -= (0,2.5) (50,97) += (0,3) -= (0,6) (1000,80) += (0,0) -= (0,0)};"),
            std::string::npos);
  EXPECT_NE(tex.find("coordinates {(5,60) (1000,61)};"), std::string::npos) << "a series without spread has no bars";
  EXPECT_EQ(occurrences(tex, "error bars/.cd"), 1u);
}

TEST(FigurePgfplots, ScatterIsMarksOnlyWithEqualAxesAndTheUnitCircle) {
  Figure figure;
  figure.name = "prototypes";
  figure.kind = FigureKind::scatter;
  figure.equal_axes = true;
  figure.draw_unit_circle = true;
  figure.series = {{"base", {0.6, gap}, {0.8, 0.1}}};
  const std::string tex = render_pgfplots(figure);
  SCOPED_TRACE(tex);
  EXPECT_TRUE(braces_balance(tex));
  // Ticks -1 to 1, the axes 4% further, in a 7 x 4.6 cm box with equal units: x widened to 7 / 4.6 of the y range.
  EXPECT_NE(tex.find(fmt::format("xmin={:.8g}, xmax={:.8g}, ymin=-1.08, ymax=1.08", -7 / 4.6 * 1.08, 7 / 4.6 * 1.08)),
            std::string::npos);
  EXPECT_NE(tex.find("\\addplot[forget plot, gray, dashed, no marks, domain=0:360, samples=91] ({cos(x)}, {sin(x)});"),
            std::string::npos);
  EXPECT_NE(tex.find("\\addplot[only marks, color=fscilfigure0, mark=*, mark options={solid}] coordinates {(0.6,0.8)};"),
            std::string::npos);
}

// Fields of one line of RFC 4180 CSV.
std::vector<std::string> csv_record(const std::string& line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted && c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
      fields.back() += '"';
      ++i;
    } else if (c == '"') {
      quoted = !quoted;
    } else if (c == ',' && !quoted) {
      fields.emplace_back();
    } else {
      fields.back() += c;
    }
  }
  return fields;
}

TEST(FigureCsv, RoundTripsEveryValueAndLabel) {
  Figure figure;
  figure.name = "sweep";
  figure.kind = FigureKind::lines;
  figure.x_categories = {"1-shot", "5,shot \"wide\""};
  figure.series = {{"cop-fscil, \"tuned\"", {0, 1}, {73.4566666666, gap}}, {"orco", {1, 0}, {0.000123456789, 1234.56789}}};
  const std::string csv = render_figure_csv(figure);
  const auto lines = csv_lines(csv);
  ASSERT_EQ(lines.size(), 5u) << csv;
  EXPECT_EQ(lines[0], "series,x,y");
  EXPECT_EQ(lines[1], "\"cop-fscil, \"\"tuned\"\"\",1-shot,73.456667");
  const std::vector<std::string> expected_x = {"1-shot", "5,shot \"wide\"", "5,shot \"wide\"", "1-shot"};
  std::size_t row = 1;
  for (const auto& series : figure.series) {
    for (std::size_t i = 0; i < series.y.size(); ++i, ++row) {
      const auto fields = csv_record(lines[row]);
      ASSERT_EQ(fields.size(), 3u) << lines[row];
      EXPECT_EQ(fields[0], series.label);
      EXPECT_EQ(fields[1], expected_x[row - 1]);
      if (std::isnan(series.y[i])) {
        EXPECT_EQ(fields[2], "");
      } else {
        EXPECT_NEAR(std::stod(fields[2]), series.y[i], std::abs(series.y[i]) * 1e-7) << lines[row];
      }
    }
  }
  const std::string numeric = render_figure_csv(lines_figure({0.125, 2}, {1e-5, 99.5}));
  EXPECT_EQ(numeric, "series,x,y\nprototype,0.125,1e-05\nprototype,2,99.5\n");
  Figure spread = lines_figure({0, 1}, {80, 70});
  spread.series[0].y_spread = {2.5, gap};
  spread.series.push_back({"orco", {0}, {60}});
  EXPECT_EQ(render_figure_csv(spread), "series,x,y,y_std\nprototype,0,80,2.5\nprototype,1,70,\norco,0,60,\n");
}

TEST(FigureWriter, WritesSvgTexAndCsvUnderFigures) {
  const TemporaryDirectory folder;
  Figure figure = lines_figure({0, 1}, {80, 70});
  write_figure(folder.path() / "shot-5", figure);
  const auto figures = folder.path() / "shot-5" / "figures";
  EXPECT_EQ(read_text_file(figures / "accuracy.svg"), render_svg(figure));
  EXPECT_EQ(read_text_file(figures / "accuracy.tex"), render_pgfplots(figure));
  EXPECT_EQ(read_text_file(figures / "accuracy.csv"), "series,x,y\nprototype,0,80\nprototype,1,70\n");

  figure.series[0].y = {60, 50};  // written again: replaced whole
  write_figure(folder.path() / "shot-5", figure);
  EXPECT_EQ(read_text_file(figures / "accuracy.csv"), "series,x,y\nprototype,0,60\nprototype,1,50\n");

  Figure refused = figure;
  refused.name = "accuracy";
  refused.series[0].y = {1};
  EXPECT_THROW(write_figure(folder.path() / "other", refused), ReportError);
  EXPECT_FALSE(std::filesystem::exists(folder.path() / "other"));  // nothing written
}

}  // namespace
}  // namespace fscil
