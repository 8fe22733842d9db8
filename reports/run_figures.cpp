#include "reports/run_figures.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "metrics/statistics.h"
#include "core/number_text.h"
#include "reports/series_labels.h"
#include "core/error.h"

namespace fscil {

namespace {

constexpr const char* kInflated = "selected on test (inflated)";
const double kNaN = std::numeric_limits<double>::quiet_NaN();

// The method and its sweep cell (row_label names the selection already).
SeriesName series_name(const SummaryRow& row) { return {row_label(row), without_key(row.grid, "selection")}; }

// "method [cell]" whole: what tells series apart while a figure is built.
std::string full_label(const SeriesName& name) { return label_with_cell(name.method, name.cell); }

void add_note(Figure& figure, const std::string& note) {
  if (note.empty() || figure.note.find(note) != std::string::npos) return;
  figure.note += (figure.note.empty() ? "" : "; ") + note;
}

// The legend entries (or the x categories) of `figure` by the one label rule: what the series
// share goes under the title.
void label_series(Figure& figure, const std::vector<SeriesName>& names) {
  SeriesLabels labels = series_labels(names, figure_legend_width);
  for (std::size_t s = 0; s < figure.series.size(); ++s) figure.series[s].label = labels.labels[s];
  add_note(figure, labels.shared);
}

void label_categories(Figure& figure, const std::vector<SeriesName>& names) {
  SeriesLabels labels = series_labels(names, figure_category_width);
  figure.x_categories = labels.labels;
  add_note(figure, labels.shared);
}

// Lower-case letters, digits, '_' and '-' of `text`, the rest as '_': a figure's file stem.
std::string stem(const std::string& text) {
  std::string out;
  for (const char c : text) {
    const bool keep = (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
    out += keep ? c : (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : '_';
  }
  return out;
}

const SeedStatistic& metric_of(const SummaryRow& row, const std::string& metric) {
  if (metric == "AA") return row.average_accuracy;
  if (metric == "PD") return row.performance_drop;
  if (metric == "ADR") return row.average_drop_rate;
  if (metric == "Acc0") return row.session_accuracy.front();
  throw ReportError(fmt::format("no metric '{}' (expected AA, PD, ADR or Acc0)", metric));
}

// One standard deviation over the seeds, where there are two or more.
double spread_of(const SeedStatistic& statistic) { return statistic.values.size() >= 2 ? statistic.std : kNaN; }
double spread_of(const std::vector<double>& values) { return values.size() >= 2 ? standard_deviation_of(values) : kNaN; }

// Says what the whiskers are, on a figure that draws any: a figure travels without its page.
void note_spread(Figure& figure) {
  if (has_spread(figure)) add_note(figure, "whiskers: one standard deviation over seeds either side");
}

void note_selection(Figure& figure, const std::string& selection) {
  if (selection == "test-oracle") add_note(figure, kInflated);
}

// Sessions as categories: whole-number ticks.
std::vector<std::string> session_categories(std::size_t sessions) {
  std::vector<std::string> names;
  for (std::size_t s = 0; s < sessions; ++s) names.push_back(std::to_string(s));
  return names;
}

// (x, y) on the line of `name`, which is added, and its name kept in `names`, where the figure has none.
void add_point(Figure& figure, std::vector<SeriesName>& names, const SeriesName& name, double x, double y,
               double spread = kNaN) {
  const std::string label = full_label(name);
  auto series = std::find_if(figure.series.begin(), figure.series.end(),
                             [&](const FigureSeries& s) { return s.label == label; });
  if (series == figure.series.end()) {
    series = figure.series.insert(figure.series.end(), {label, {}, {}});
    names.push_back(name);
  }
  series->x.push_back(x);
  series->y.push_back(y);
  series->y_spread.push_back(spread);
}

// Where each of a sweep key's `values` sits on the x axis of `figure`, which this sets up: at the
// number itself where every value is one, on a logarithmic axis where they are positive and the
// largest is more than 20 times the smallest (N_ps 5 to 1000); as categories where a value is not
// a number, or where such a span includes 0 or a negative value, which have no logarithm
// (pic_weight 0, 0.0001 ... 1); on a linear axis otherwise (shot 1 to 5).
std::vector<double> place_values(Figure& figure, const std::vector<std::string>& values) {
  std::vector<double> numbers;
  for (const auto& value : values) {
    const auto number = parse_finite_number(value);
    if (!number) break;
    numbers.push_back(*number);
  }
  if (numbers.size() == values.size() && !numbers.empty()) {
    const double low = *std::min_element(numbers.begin(), numbers.end());
    const double high = *std::max_element(numbers.begin(), numbers.end());
    double smallest_positive = HUGE_VAL;
    for (const double number : numbers) {
      if (number > 0) smallest_positive = std::min(smallest_positive, number);
    }
    const bool wide = high > 20 * smallest_positive;
    if (!wide) return numbers;
    if (low > 0) {
      figure.x_log = true;
      return numbers;
    }
  }
  figure.x_categories = values;
  std::vector<double> positions;
  for (std::size_t i = 0; i < values.size(); ++i) positions.push_back(static_cast<double>(i));
  return positions;
}

// Points of each line in the order of x, so a line runs left to right.
void sort_points(Figure& figure) {
  for (auto& series : figure.series) {
    std::vector<std::size_t> order(series.x.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return series.x[a] < series.x[b]; });
    FigureSeries sorted{series.label, {}, {}};
    for (std::size_t i : order) {
      sorted.x.push_back(series.x[i]);
      sorted.y.push_back(series.y[i]);
      if (!series.y_spread.empty()) sorted.y_spread.push_back(series.y_spread[i]);
    }
    series = std::move(sorted);
  }
}

}  // namespace

Figure session_accuracy_figure(const SummaryTable& table, const std::string& dataset, SessionMetric metric) {
  static const std::map<SessionMetric, std::pair<const char*, const char*>> kNames = {
      {SessionMetric::all, {"all", "accuracy on all seen classes (%)"}},
      {SessionMetric::base, {"base", "accuracy on the base classes (%)"}},
      {SessionMetric::novel, {"novel", "accuracy on the novel classes (%)"}},
      {SessionMetric::harmonic, {"harmonic", "harmonic mean of base and novel accuracy (%)"}}};
  const auto& [suffix, y_label] = kNames.at(metric);
  Figure figure;
  figure.name = stem(fmt::format("sessions_{}_{}", dataset, suffix));
  figure.title = fmt::format("Accuracy per session on {} ({}, {} split{})", dataset, suffix, table.evaluated_on,
                             table.title_note());
  figure.x_label = "session";
  figure.y_label = y_label;
  figure.y_floor = 0;
  figure.y_ceiling = 100;
  std::vector<SeriesName> names;
  for (const auto& row : table.rows) {
    if (row.dataset != dataset) continue;
    const auto& values = metric == SessionMetric::all        ? row.session_accuracy
                         : metric == SessionMetric::base     ? row.session_base_accuracy
                         : metric == SessionMetric::novel    ? row.session_novel_accuracy
                                                             : row.session_harmonic_mean;
    names.push_back(series_name(row));
    FigureSeries series{full_label(names.back()), {}, {}};
    for (std::size_t s = 0; s < values.size(); ++s) {
      series.x.push_back(static_cast<double>(s));
      // Session 0 has no novel classes.
      const bool undefined = s == 0 && (metric == SessionMetric::novel || metric == SessionMetric::harmonic);
      series.y.push_back(undefined ? kNaN : values[s].mean);
      series.y_spread.push_back(undefined ? kNaN : spread_of(values[s]));
    }
    figure.x_categories = session_categories(std::max(figure.x_categories.size(), values.size()));
    figure.series.push_back(std::move(series));
    note_selection(figure, row.selection);
  }
  label_series(figure, names);
  note_spread(figure);
  return figure;
}

Figure context_ratio_figure(const std::vector<RunRecord>& records, const std::string& dataset) {
  Figure figure;
  figure.name = stem("context_ratio_" + dataset);
  figure.title = fmt::format("Context-to-class dispersion R per session on {}", dataset);
  figure.x_label = "session";
  figure.y_label = "R (mean over classes and seeds)";
  figure.y_floor = 0;  // a ratio of dispersions
  // (label) -> per session the values of its seeds
  std::vector<std::pair<SeriesName, std::vector<std::vector<double>>>> lines;
  for (const auto& record : records) {
    if (record.dataset != dataset) continue;
    SummaryRow row;
    row.method = record.method;
    row.grid = record.grid;
    row.selection = record.selection;
    const SeriesName name = series_name(row);
    auto line = std::find_if(lines.begin(), lines.end(),
                             [&](const auto& entry) { return full_label(entry.first) == full_label(name); });
    if (line == lines.end()) line = lines.insert(lines.end(), {name, {}});
    for (const auto& session : record.sessions) {
      if (std::isnan(session.context_ratio_mean)) continue;
      if (line->second.size() <= static_cast<std::size_t>(session.session)) line->second.resize(session.session + 1);
      line->second[session.session].push_back(session.context_ratio_mean);
    }
    note_selection(figure, record.selection);
  }
  std::vector<SeriesName> names;
  for (const auto& [name, sessions] : lines) {
    if (sessions.empty()) continue;
    names.push_back(name);
    FigureSeries series{full_label(name), {}, {}};
    for (std::size_t s = 0; s < sessions.size(); ++s) {
      series.x.push_back(static_cast<double>(s));
      series.y.push_back(sessions[s].empty() ? kNaN : mean_of(sessions[s]));
      series.y_spread.push_back(spread_of(sessions[s]));
    }
    figure.x_categories = session_categories(std::max(figure.x_categories.size(), sessions.size()));
    figure.series.push_back(std::move(series));
  }
  const bool all_zero = !figure.series.empty() && std::all_of(figure.series.begin(), figure.series.end(), [](const auto& series) {
    return std::all_of(series.y.begin(), series.y.end(), [](double r) { return !std::isfinite(r) || r == 0; });
  });
  if (all_zero) add_note(figure, "R is 0 throughout: the scored split holds one context per class");
  label_series(figure, names);
  note_spread(figure);
  return figure;
}

std::vector<Figure> efficiency_figures(const std::vector<CostRow>& costs, const std::string& dataset) {
  struct Panel {
    const char* suffix;
    const char* y_label;
    double (*value)(const CostRow&);
  };
  const Panel panels[] = {{"flops", "FLOPs per sample (M)", [](const CostRow& r) { return r.mega_flops; }},
                          {"params", "parameters NP (M)", [](const CostRow& r) { return r.parameters_millions; }},
                          {"it", "inference time IT (ms per sample)",
                           [](const CostRow& r) { return r.inference_ms_per_sample; }}};
  std::vector<Figure> figures;
  for (const auto& panel : panels) {
    Figure figure;
    figure.name = stem(fmt::format("efficiency_{}_{}", dataset, panel.suffix));
    figure.title = fmt::format("Computational efficiency on {}: {}", dataset, panel.y_label);
    figure.kind = FigureKind::bars;
    figure.x_label = "method";
    figure.y_label = panel.y_label;
    figure.y_floor = 0;
    FigureSeries series{"", {}, {}};
    std::vector<SeriesName> names;
    for (const auto& row : costs) {
      if (row.dataset != dataset) continue;
      series.x.push_back(static_cast<double>(names.size()));
      series.y.push_back(panel.value(row));
      names.push_back({row.method, row.grid});
    }
    figure.series.push_back(std::move(series));
    label_categories(figure, names);
    figures.push_back(std::move(figure));
  }
  return figures;
}

Figure ablation_figure(const SummaryTable& table, const std::string& dataset, const std::string& name) {
  Figure figure;
  figure.name = stem(name);
  figure.title = fmt::format("Ablation on {} ({} split{})", dataset, table.evaluated_on, table.title_note());
  figure.kind = FigureKind::bars;
  figure.x_label = "variant";
  figure.y_label = "%";
  FigureSeries aa{"AA", {}, {}}, pd{"PD", {}, {}};
  std::vector<SeriesName> names;
  for (const auto& row : table.rows) {
    if (row.dataset != dataset) continue;
    const double x = static_cast<double>(names.size());
    names.push_back(series_name(row));
    aa.x.push_back(x);
    aa.y.push_back(row.average_accuracy.mean);
    aa.y_spread.push_back(spread_of(row.average_accuracy));
    pd.x.push_back(x);
    pd.y.push_back(row.performance_drop.mean);
    pd.y_spread.push_back(spread_of(row.performance_drop));
    note_selection(figure, row.selection);
  }
  figure.series = {aa, pd};
  label_categories(figure, names);
  note_spread(figure);
  return figure;
}

Figure grid_metric_figure(const SummaryTable& table, const std::string& dataset, const std::string& key,
                          const std::vector<std::string>& values, const std::string& metric, const std::string& name,
                          const std::string& title) {
  Figure figure;
  figure.name = stem(name);
  figure.title = title;
  figure.x_label = key;
  figure.y_label = metric == "Acc0" ? "session 0 accuracy (%)" : metric + (metric == "ADR" ? "" : " (%)");
  if (metric == "AA" || metric == "Acc0") figure.y_floor = 0, figure.y_ceiling = 100;
  const std::vector<double> positions = place_values(figure, values);
  std::vector<SeriesName> names;
  for (const auto& row : table.rows) {
    const std::string* value = grid_value(row.grid, key);
    if (row.dataset != dataset || value == nullptr) continue;
    const auto position = std::find(values.begin(), values.end(), *value);
    if (position == values.end()) continue;
    // One line per method and value of the other keys.
    SummaryRow line_key = row;
    line_key.grid = without_key(row.grid, key);
    const SeedStatistic& value_of_row = metric_of(row, metric);
    add_point(figure, names, series_name(line_key), positions[position - values.begin()], value_of_row.mean,
              spread_of(value_of_row));
    note_selection(figure, row.selection);
  }
  sort_points(figure);
  label_series(figure, names);
  note_spread(figure);
  return figure;
}

Figure grid_update_time_figure(const std::vector<CostRow>& costs, const std::string& dataset, const std::string& key,
                               const std::vector<std::string>& values, const std::string& name,
                               const std::string& title) {
  Figure figure;
  figure.name = stem(name);
  figure.title = title;
  figure.x_label = key;
  figure.y_label = "time per incremental session (s)";
  figure.y_floor = 0;
  const std::vector<double> positions = place_values(figure, values);
  std::vector<SeriesName> names;
  for (const auto& row : costs) {
    const std::string* value = grid_value(row.grid, key);
    if (row.dataset != dataset || value == nullptr) continue;
    const auto position = std::find(values.begin(), values.end(), *value);
    if (position == values.end()) continue;
    // One line per method and value of the other keys.
    add_point(figure, names, {row.method, without_key(row.grid, key)}, positions[position - values.begin()],
              row.update_seconds);
  }
  sort_points(figure);
  label_series(figure, names);
  return figure;
}

}  // namespace fscil
