#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>

#include "reports/latex_text.h"
#include "reports/summary_table.h"

namespace fscil {

namespace {

std::size_t max_sessions(const std::vector<const SummaryRow*>& rows) {
  std::size_t sessions = 0;
  for (const auto* row : rows) sessions = std::max(sessions, row->session_accuracy.size());
  return sessions;
}

std::vector<const SummaryRow*> rows_of(const SummaryTable& table, const std::string& dataset) {
  std::vector<const SummaryRow*> rows;
  for (const auto& row : table.rows) {
    if (row.dataset == dataset) rows.push_back(&row);
  }
  return rows;
}

// The columns of the paper's tables, each with the direction that is better.
struct Column {
  std::string title;
  std::function<const SeedStatistic*(const SummaryRow&)> value;
  bool higher_is_better;
};

std::vector<Column> paper_columns(std::size_t sessions) {
  std::vector<Column> columns;
  for (std::size_t s = 0; s < sessions; ++s) {
    columns.push_back({std::to_string(s),
                       [s](const SummaryRow& row) {
                         return s < row.session_accuracy.size() ? &row.session_accuracy[s] : nullptr;
                       },
                       true});
  }
  columns.push_back({"PD", [](const SummaryRow& row) { return &row.performance_drop; }, false});
  columns.push_back({"AA", [](const SummaryRow& row) { return &row.average_accuracy; }, true});
  columns.push_back({"ADR", [](const SummaryRow& row) { return &row.average_drop_rate; }, false});
  return columns;
}

// Best means after rounding to the two decimals shown, so ties are all marked; among honest rows
// only (epochs chosen on test are never best).
bool is_best(const Column& column, const SummaryRow& row, const std::vector<const SummaryRow*>& rows) {
  const SeedStatistic* mine = column.value(row);
  if (mine == nullptr || rows.size() < 2 || row.selection == "test-oracle") return false;
  const double shown = std::round(mine->mean * 100);
  for (const auto* other : rows) {
    const SeedStatistic* theirs = column.value(*other);
    if (theirs == nullptr || other->selection == "test-oracle") continue;
    const double value = std::round(theirs->mean * 100);
    if (column.higher_is_better ? value > shown : value < shown) return false;
  }
  return true;
}

// mean, or over several seeds "mean ± std [95% CI]"; `interval` wraps the bracketed interval.
std::string cell(const SeedStatistic* statistic, bool with_std, const char* plus_minus,
                 const char* interval = "[{:.2f}, {:.2f}]") {
  if (statistic == nullptr) return "";
  if (!with_std) return fmt::format("{:.2f}", statistic->mean);
  return fmt::format("{:.2f}{}{:.2f} ", statistic->mean, plus_minus, statistic->std) +
         fmt::format(fmt::runtime(interval), statistic->mean - statistic->ci95, statistic->mean + statistic->ci95);
}

// A row whose base training was still rising, or did not learn, is marked; its footnote says how.
std::string marked_label_suffix(const SummaryRow& row, const char* dagger) {
  return ended_unfinished(row.training) ? dagger : "";
}

constexpr const char* kUnfinishedNote =
    "a base stage ended still rising on base validation (the best of its last 3 epochs at least a point above "
    "the best before them; docs/methods.md, \"Did the training finish?\"): not measured at its plateau; or "
    "its loss never moved: not learning";

std::string cell_value(const SummaryRow& row, const std::string& key) {
  const std::string* value = grid_value(row.grid, key);
  return value == nullptr ? std::string() : *value;
}

}  // namespace

std::string render_csv(const SummaryTable& table) {
  std::vector<const SummaryRow*> all;
  for (const auto& row : table.rows) all.push_back(&row);
  const std::size_t sessions = max_sessions(all);
  const bool with_std = table.several_seeds();
  const auto grid_keys = table.grid_keys();
  std::string out = "method,dataset";
  for (const auto& key : grid_keys) out += "," + key;
  out += ",split,selection,precision,seeds,AA,PD,ADR";
  for (std::size_t s = 0; s < sessions; ++s) out += fmt::format(",acc_{}", s);
  if (with_std) {
    out += ",AA_std,PD_std,ADR_std";
    for (std::size_t s = 0; s < sessions; ++s) out += fmt::format(",acc_{}_std", s);
    out += ",AA_ci95,PD_ci95,ADR_ci95";
    for (std::size_t s = 0; s < sessions; ++s) out += fmt::format(",acc_{}_ci95", s);
  }
  out += ",training\n";
  for (const auto* row : all) {
    out += fmt::format("{},{}", row->method, row->dataset);
    for (const auto& key : grid_keys) out += "," + cell_value(*row, key);
    out += fmt::format(",{},{},{},{},{:.4f},{:.4f},{:.4f}", table.evaluated_on, row->selection, table.precision,
                       fmt::join(row->seeds, " "),
                       row->average_accuracy.mean, row->performance_drop.mean, row->average_drop_rate.mean);
    for (std::size_t s = 0; s < sessions; ++s) {
      out += s < row->session_accuracy.size() ? fmt::format(",{:.4f}", row->session_accuracy[s].mean) : ",";
    }
    if (with_std) {
      out += fmt::format(",{:.4f},{:.4f},{:.4f}", row->average_accuracy.std, row->performance_drop.std,
                         row->average_drop_rate.std);
      for (std::size_t s = 0; s < sessions; ++s) {
        out += s < row->session_accuracy.size() ? fmt::format(",{:.4f}", row->session_accuracy[s].std) : ",";
      }
      out += fmt::format(",{:.4f},{:.4f},{:.4f}", row->average_accuracy.ci95, row->performance_drop.ci95,
                         row->average_drop_rate.ci95);
      for (std::size_t s = 0; s < sessions; ++s) {
        out += s < row->session_accuracy.size() ? fmt::format(",{:.4f}", row->session_accuracy[s].ci95) : ",";
      }
    }
    out += fmt::format(",{}\n", verdict_name(row->training));
  }
  return out;
}

std::string render_latex(const SummaryTable& table, const std::string& what) {
  const bool with_std = table.several_seeds();
  std::string out = "% fscil-bench results; requires \\usepackage{booktabs,multirow}\n";
  for (const auto& dataset : table.datasets()) {
    const auto rows = rows_of(table, dataset);
    const auto columns = paper_columns(max_sessions(rows));
    const std::size_t sessions = columns.size() - 3;
    out += "\\begin{table*}[!t]\n\\centering\n";
    out += fmt::format("\\caption{{{} on {}, {} split{}{}.}}\n", latex_text(what), latex_text(dataset), table.evaluated_on,
                       table.precision_note(),
                       with_std ? " (mean $\\pm$ std over seeds, [95\\% confidence interval, Student t])" : "");
    const auto grid_keys = table.grid_keys();
    out += fmt::format("\\begin{{tabular}}{{{}l{}ccc}}\n\\toprule\n", std::string(grid_keys.size(), 'l'),
                       std::string(sessions, 'c'));
    for (const auto& key : grid_keys) out += fmt::format("\\multirow{{2}}{{*}}{{{}}} & ", latex_text(key));
    out += fmt::format("\\multirow{{2}}{{*}}{{Method}} & \\multicolumn{{{}}}{{c}}{{Accuracy in each session $\\uparrow$}}"
                       " & \\multirow{{2}}{{*}}{{PD$\\downarrow$}} & \\multirow{{2}}{{*}}{{AA$\\uparrow$}}"
                       " & \\multirow{{2}}{{*}}{{ADR$\\downarrow$}} \\\\\n",
                       sessions);
    out += fmt::format("\\cmidrule(lr){{{}-{}}}\n", grid_keys.size() + 2, grid_keys.size() + sessions + 1);
    out += std::string(grid_keys.size() * 2, ' ');
    for (std::size_t k = 0; k < grid_keys.size(); ++k) out += "&";
    for (std::size_t s = 0; s < sessions; ++s) out += fmt::format(" & {}", s);
    out += " & & & \\\\\n\\midrule\n";
    for (const auto* row : rows) {
      for (const auto& key : grid_keys) out += latex_text(cell_value(*row, key)) + " & ";
      out += latex_text(row_label(*row)) + marked_label_suffix(*row, "$^\\dagger$");
      for (const auto& column : columns) {
        const std::string text = cell(column.value(*row), with_std, "$\\pm$", "{{\\scriptsize[{:.2f}, {:.2f}]}}");
        out += is_best(column, *row, rows) ? fmt::format(" & \\textbf{{{}}}", text) : fmt::format(" & {}", text);
      }
      out += " \\\\\n";
    }
    out += "\\bottomrule\n\\end{tabular}\n";
    if (const auto notes = unfinished_notes(rows); !notes.empty()) {
      out += fmt::format("\\par\\footnotesize $^\\dagger$ {}: {}.\n", latex_text(kUnfinishedNote),
                         latex_text(fmt::format("{}", fmt::join(notes, "; "))));
    }
    out += "\\end{table*}\n\n";
  }
  return out;
}

std::string render_markdown(const SummaryTable& table) {
  const bool with_std = table.several_seeds();
  std::string out;
  for (const auto& dataset : table.datasets()) {
    const auto rows = rows_of(table, dataset);
    const auto columns = paper_columns(max_sessions(rows));
    const auto grid_keys = table.grid_keys();
    out += fmt::format("### {}, {} split{}{}\n\n|", dataset, table.evaluated_on, table.precision_note(), with_std ? " (mean ± std over seeds [95% confidence interval, Student t])" : "");
    for (const auto& key : grid_keys) out += fmt::format(" {} |", key);
    out += " method |";
    for (const auto& column : columns) out += fmt::format(" {} |", column.title);
    out += "\n|";
    for (std::size_t k = 0; k < grid_keys.size(); ++k) out += "---|";
    out += "---|";
    for (std::size_t c = 0; c < columns.size(); ++c) out += "---:|";
    out += "\n";
    for (const auto* row : rows) {
      out += "|";
      for (const auto& key : grid_keys) out += fmt::format(" {} |", cell_value(*row, key));
      out += fmt::format(" {}{} |", row_label(*row), marked_label_suffix(*row, " †"));
      for (const auto& column : columns) {
        const std::string text = cell(column.value(*row), with_std, " ± ");
        out += is_best(column, *row, rows) ? fmt::format(" **{}** |", text) : fmt::format(" {} |", text);
      }
      out += "\n";
    }
    out += "\n";
    if (const auto notes = unfinished_notes(rows); !notes.empty()) {
      out += fmt::format("† {}:\n", kUnfinishedNote);
      for (const auto& note : notes) out += fmt::format("- {}\n", note);
      out += "\n";
    }
  }
  return out;
}

}  // namespace fscil
