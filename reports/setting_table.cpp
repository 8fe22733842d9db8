#include "reports/setting_table.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "reports/csv_fields.h"
#include "reports/latex_text.h"
#include "reports/paper_comparison.h"
#include "core/error.h"
#include "core/text_file.h"

namespace fscil {

namespace {

const char* const kHeader = "table,dataset,setting,Acc0,PD,AA,ADR,update_seconds";

double number_or_nan(const std::string& text, const std::string& where) {
  return text.empty() ? std::numeric_limits<double>::quiet_NaN() : finite_number(text, where);
}

std::string shown(double value, const char* format = "{:.2f}") {
  return std::isnan(value) ? std::string() : fmt::format(fmt::runtime(format), value);
}

struct Metric {
  const char* name;
  const char* latex;  // its column heading in LaTeX
  double SettingTable::Row::*ours;
  double PaperSetting::*paper;
  bool higher_is_better;
};

std::vector<Metric> metrics_of(const SettingTable& table) {
  std::vector<Metric> metrics = {{"Acc0", "$\\mathrm{Acc}_{0}$", &SettingTable::Row::acc0, &PaperSetting::acc0, true},
                                 {"PD", "PD", &SettingTable::Row::pd, &PaperSetting::pd, false},
                                 {"AA", "AA", &SettingTable::Row::aa, &PaperSetting::aa, true},
                                 {"ADR", "ADR", &SettingTable::Row::adr, &PaperSetting::adr, false}};
  if (table.update_time) {
    metrics.push_back({"update_s", "Update time (s)", &SettingTable::Row::update_seconds, &PaperSetting::update_seconds,
                       false});
  }
  return metrics;
}

// Best after rounding to the two decimals shown, over honest rows only.
bool is_best(const SettingTable& table, const SettingTable::Row& row, const Metric& metric) {
  if (row.selected_on_test || table.rows.size() < 2) return false;
  const double mine = std::round(row.*metric.ours * 100);
  for (const auto& other : table.rows) {
    if (other.selected_on_test) continue;
    const double theirs = std::round(other.*metric.ours * 100);
    if (metric.higher_is_better ? theirs > mine : theirs < mine) return false;
  }
  return true;
}

std::string label_of(const SettingTable::Row& row) {
  return row.selected_on_test ? row.setting + " (selected on test (inflated))" : row.setting;
}

// The row's cell as the paper's table names it, "$N_{\mathrm{ps}}$ = 5", or as typed where it has
// no name for the key; keys joined by ", ".
std::string latex_label_of(const SettingTable& table, const SettingTable::Row& row) {
  std::vector<std::string> parts;
  for (const auto& [key, value] : row.cell) {
    const auto symbol = std::find_if(table.latex_keys.begin(), table.latex_keys.end(),
                                     [&](const auto& entry) { return entry.first == key; });
    parts.push_back(symbol == table.latex_keys.end() ? latex_text(key + "=" + value)
                                                     : fmt::format("{} = {}", symbol->second, latex_text(value)));
  }
  std::string label = parts.empty() ? latex_text(row.setting) : fmt::format("{}", fmt::join(parts, ", "));
  return row.selected_on_test ? label + " (selected on test (inflated))" : label;
}

}  // namespace

std::vector<PaperSetting> load_paper_analyses(const std::filesystem::path& path) {
  const std::vector<std::string> lines = csv_lines(read_text_file(path));
  if (lines.empty() || lines[0] != kHeader) {
    throw ReportError(fmt::format("{}:1: header must be '{}'", path.string(), kHeader));
  }
  std::vector<PaperSetting> rows;
  for (std::size_t number = 1; number < lines.size(); ++number) {
    if (lines[number].empty()) continue;
    const std::string where = fmt::format("{}:{}", path.string(), number + 1);
    const auto fields = csv_fields(lines[number]);
    if (fields.size() != 8) throw ReportError(fmt::format("{}: {} fields, expected 8", where, fields.size()));
    rows.push_back({fields[0], fields[1], fields[2], number_or_nan(fields[3], where + " Acc0"),
                    number_or_nan(fields[4], where + " PD"), number_or_nan(fields[5], where + " AA"),
                    number_or_nan(fields[6], where + " ADR"), number_or_nan(fields[7], where + " update_seconds")});
  }
  return rows;
}

SettingTable make_setting_table(const std::string& name, const std::string& caption, const std::string& method,
                                const std::string& dataset, const SummaryTable& table,
                                const std::vector<CostRow>& costs, const std::vector<PaperSetting>& paper,
                                bool update_time, std::vector<std::pair<std::string, std::string>> latex_keys) {
  SettingTable result{name, caption, method, dataset, update_time, std::move(latex_keys), {}};
  // The paper's numbers are test-split numbers: none beside runs scored on validation.
  const std::string paper_dataset =
      table.evaluated_on == "test" && table.removal == "none" ? paper_dataset_of(dataset) : std::string();
  for (const auto& row : table.rows) {
    if (row.method != method || row.dataset != dataset) continue;
    SettingTable::Row line;
    line.setting = grid_cell_name(row.grid);
    line.cell = row.grid;
    line.seeds = fmt::format("{}", fmt::join(row.seeds, " "));
    line.acc0 = row.session_accuracy.front().mean;
    line.pd = row.performance_drop.mean;
    line.aa = row.average_accuracy.mean;
    line.adr = row.average_drop_rate.mean;
    line.selected_on_test = row.selection == "test-oracle";
    line.update_seconds = std::numeric_limits<double>::quiet_NaN();
    for (const auto& cost : costs) {
      if (cost.method == method && cost.dataset == dataset && same_cell(cost.grid, row.grid)) {
        line.update_seconds = cost.update_seconds;
      }
    }
    for (const auto& published : paper) {
      if (published.table == name && published.dataset == paper_dataset && published.setting == line.setting) {
        line.paper = published;
      }
    }
    result.rows.push_back(std::move(line));
  }
  if (result.rows.empty()) {
    throw ReportError(fmt::format("{}: no run of {} on {} in these results", name, method, dataset));
  }
  return result;
}

std::string render_setting_csv(const SettingTable& table) {
  const auto metrics = metrics_of(table);
  std::string out = "table,dataset,method,setting,seeds,selected_on_test";
  for (const auto& metric : metrics) out += fmt::format(",{}", metric.name);
  for (const auto& metric : metrics) out += fmt::format(",paper_{}", metric.name);
  out += "\n";
  for (const auto& row : table.rows) {
    out += fmt::format("{},{},{},{},{},{}", table.name, table.dataset, table.method, row.setting, row.seeds,
                       row.selected_on_test ? "yes" : "no");
    for (const auto& metric : metrics) out += "," + shown(row.*metric.ours, "{:.4f}");
    for (const auto& metric : metrics) out += "," + (row.paper ? shown((*row.paper).*metric.paper) : std::string());
    out += "\n";
  }
  return out;
}

std::string render_setting_markdown(const SettingTable& table) {
  const auto metrics = metrics_of(table);
  bool simulated = false;
  const std::string paper_dataset = paper_dataset_of(table.dataset, &simulated);
  std::string out = fmt::format("### {}: {} on {}{}\n\n| setting |", table.caption, table.method, table.dataset,
                                paper_dataset.empty() ? ""
                                : simulated ? fmt::format(" (simulated {}; paper's numbers in brackets)", paper_dataset)
                                            : " (paper's numbers in brackets)");
  for (const auto& metric : metrics) out += fmt::format(" {} |", metric.name);
  out += "\n|---|";
  for (std::size_t m = 0; m < metrics.size(); ++m) out += "---:|";
  out += "\n";
  for (const auto& row : table.rows) {
    out += fmt::format("| {} |", label_of(row));
    for (const auto& metric : metrics) {
      std::string text = shown(row.*metric.ours);
      if (is_best(table, row, metric)) text = "**" + text + "**";
      if (row.paper && !std::isnan((*row.paper).*metric.paper)) text += " (" + shown((*row.paper).*metric.paper) + ")";
      out += " " + text + " |";
    }
    out += "\n";
  }
  return out + "\n";
}

std::string render_setting_latex(const SettingTable& table) {
  const auto metrics = metrics_of(table);
  std::string out = "% fscil-bench; requires \\usepackage{booktabs}\n\\begin{table}[!t]\n\\centering\n";
  out += fmt::format("\\caption{{{} ({} on {}; the paper's numbers in brackets where it gives them).}}\n",
                     latex_text(table.caption), latex_text(table.method), latex_text(table.dataset));
  out += fmt::format("\\begin{{tabular}}{{l{}}}\n\\toprule\nSetting", std::string(metrics.size(), 'c'));
  for (const auto& metric : metrics) {
    out += fmt::format(" & {}{}", metric.latex, metric.higher_is_better ? "$\\uparrow$" : "$\\downarrow$");
  }
  out += " \\\\\n\\midrule\n";
  for (const auto& row : table.rows) {
    out += latex_label_of(table, row);
    for (const auto& metric : metrics) {
      std::string text = shown(row.*metric.ours);
      if (is_best(table, row, metric)) text = "\\textbf{" + text + "}";
      if (row.paper && !std::isnan((*row.paper).*metric.paper)) text += " (" + shown((*row.paper).*metric.paper) + ")";
      out += " & " + text;
    }
    out += " \\\\\n";
  }
  return out + "\\bottomrule\n\\end{tabular}\n\\end{table}\n";
}

}  // namespace fscil
