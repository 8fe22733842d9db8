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

// Best means after rounding to the two decimals shown, so ties are all marked.
bool is_best(const Column& column, const SummaryRow& row, const std::vector<const SummaryRow*>& rows) {
  const SeedStatistic* mine = column.value(row);
  if (mine == nullptr || rows.size() < 2) return false;
  const double shown = std::round(mine->mean * 100);
  for (const auto* other : rows) {
    const SeedStatistic* theirs = column.value(*other);
    if (theirs == nullptr) continue;
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

}  // namespace

std::string render_csv(const SummaryTable& table) {
  std::vector<const SummaryRow*> all;
  for (const auto& row : table.rows) all.push_back(&row);
  const std::size_t sessions = max_sessions(all);
  const bool with_std = table.several_seeds();
  std::string out = "method,dataset,split,seeds,AA,PD,ADR";
  for (std::size_t s = 0; s < sessions; ++s) out += fmt::format(",acc_{}", s);
  if (with_std) {
    out += ",AA_std,PD_std,ADR_std";
    for (std::size_t s = 0; s < sessions; ++s) out += fmt::format(",acc_{}_std", s);
    out += ",AA_ci95,PD_ci95,ADR_ci95";
    for (std::size_t s = 0; s < sessions; ++s) out += fmt::format(",acc_{}_ci95", s);
  }
  out += "\n";
  for (const auto* row : all) {
    out += fmt::format("{},{},{},{},{:.4f},{:.4f},{:.4f}", row->method, row->dataset, table.evaluated_on,
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
    out += "\n";
  }
  return out;
}

std::string render_sessions_csv(const SummaryTable& table) {
  std::string out = "method,dataset,split,seeds,session,accuracy,accuracy_std,base,base_std,novel,novel_std,"
                    "harmonic_mean,harmonic_mean_std\n";
  const auto both = [](const SeedStatistic& statistic) { return fmt::format("{:.4f},{:.4f}", statistic.mean, statistic.std); };
  for (const auto& row : table.rows) {
    for (std::size_t s = 0; s < row.session_accuracy.size(); ++s) {
      out += fmt::format("{},{},{},{},{},{},{},{},{}\n", row.method, row.dataset, table.evaluated_on,
                         fmt::join(row.seeds, " "), s, both(row.session_accuracy[s]), both(row.session_base_accuracy[s]),
                         s == 0 ? "," : both(row.session_novel_accuracy[s]),
                         s == 0 ? "," : both(row.session_harmonic_mean[s]));
    }
  }
  return out;
}

std::string render_latex(const SummaryTable& table) {
  const bool with_std = table.several_seeds();
  std::string out = "% fscil-bench results; requires \\usepackage{booktabs,multirow}\n";
  for (const auto& dataset : table.datasets()) {
    const auto rows = rows_of(table, dataset);
    const auto columns = paper_columns(max_sessions(rows));
    const std::size_t sessions = columns.size() - 3;
    out += "\\begin{table*}[!t]\n\\centering\n";
    out += fmt::format("\\caption{{Comparison on {}, {} split{}.}}\n", latex_text(dataset), table.evaluated_on,
                       with_std ? " (mean $\\pm$ std over seeds, [95\\% confidence interval, Student t])" : "");
    out += fmt::format("\\begin{{tabular}}{{l{}ccc}}\n\\toprule\n", std::string(sessions, 'c'));
    out += fmt::format("\\multirow{{2}}{{*}}{{Method}} & \\multicolumn{{{}}}{{c}}{{Accuracy in each session $\\uparrow$}}"
                       " & \\multirow{{2}}{{*}}{{PD$\\downarrow$}} & \\multirow{{2}}{{*}}{{AA$\\uparrow$}}"
                       " & \\multirow{{2}}{{*}}{{ADR$\\downarrow$}} \\\\\n",
                       sessions);
    out += fmt::format("\\cmidrule(lr){{2-{}}}\n", sessions + 1);
    for (std::size_t s = 0; s < sessions; ++s) out += fmt::format(" & {}", s);
    out += " & & & \\\\\n\\midrule\n";
    for (const auto* row : rows) {
      out += latex_text(row->method);
      for (const auto& column : columns) {
        const std::string text = cell(column.value(*row), with_std, "$\\pm$", "{{\\scriptsize[{:.2f}, {:.2f}]}}");
        out += is_best(column, *row, rows) ? fmt::format(" & \\textbf{{{}}}", text) : fmt::format(" & {}", text);
      }
      out += " \\\\\n";
    }
    out += "\\bottomrule\n\\end{tabular}\n\\end{table*}\n\n";
  }
  return out;
}

std::string render_markdown(const SummaryTable& table) {
  const bool with_std = table.several_seeds();
  std::string out;
  for (const auto& dataset : table.datasets()) {
    const auto rows = rows_of(table, dataset);
    const auto columns = paper_columns(max_sessions(rows));
    out += fmt::format("### {}, {} split{}\n\n| method |", dataset, table.evaluated_on, with_std ? " (mean ± std over seeds [95% confidence interval, Student t])" : "");
    for (const auto& column : columns) out += fmt::format(" {} |", column.title);
    out += "\n|---|";
    for (std::size_t c = 0; c < columns.size(); ++c) out += "---:|";
    out += "\n";
    for (const auto* row : rows) {
      out += fmt::format("| {} |", row->method);
      for (const auto& column : columns) {
        const std::string text = cell(column.value(*row), with_std, " ± ");
        out += is_best(column, *row, rows) ? fmt::format(" **{}** |", text) : fmt::format(" {} |", text);
      }
      out += "\n";
    }
    out += "\n";
  }
  return out;
}

}  // namespace fscil
