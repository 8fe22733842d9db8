#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>

#include "core/csv_text.h"
#include "metrics/statistics.h"
#include "reports/latex_text.h"
#include "reports/paper_comparison.h"
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

// The columns of the paper's tables, each with the direction that is better and the range its
// values can take (an interval is clipped to it).
struct Column {
  std::string title;
  std::function<const SeedStatistic*(const SummaryRow&)> value;
  bool higher_is_better;
  double low = -HUGE_VAL, high = HUGE_VAL;
};

std::vector<Column> paper_columns(std::size_t sessions) {
  std::vector<Column> columns;
  for (std::size_t s = 0; s < sessions; ++s) {
    columns.push_back({std::to_string(s),
                       [s](const SummaryRow& row) {
                         return s < row.session_accuracy.size() ? &row.session_accuracy[s] : nullptr;
                       },
                       true, 0, 100});
  }
  columns.push_back({"PD", [](const SummaryRow& row) { return &row.performance_drop; }, false, -100, 100});
  columns.push_back({"AA", [](const SummaryRow& row) { return &row.average_accuracy; }, true, 0, 100});
  columns.push_back({"ADR", [](const SummaryRow& row) { return &row.average_drop_rate; }, false, -HUGE_VAL, 100});
  return columns;
}

// The values of `a` and `b` on the seeds both rows ran, paired by seed.
std::pair<std::vector<double>, std::vector<double>> paired_values(const SummaryRow& a, const SeedStatistic& of_a,
                                                                  const SummaryRow& b, const SeedStatistic& of_b) {
  std::pair<std::vector<double>, std::vector<double>> pairs;
  for (std::size_t i = 0; i < a.seeds.size() && i < of_a.values.size(); ++i) {
    const auto j = std::find(b.seeds.begin(), b.seeds.end(), a.seeds[i]) - b.seeds.begin();
    if (static_cast<std::size_t>(j) >= of_b.values.size()) continue;
    pairs.first.push_back(of_a.values[i]);
    pairs.second.push_back(of_b.values[j]);
  }
  return pairs;
}

// Which rows of a column are bold. The best mean (after rounding to the two decimals shown, so
// ties are all bold; among honest rows only: epochs chosen on test are never best) of the rows
// with the most seeds, and every row a paired t-test over the seeds both ran cannot separate
// from it (two-sided, Holm-corrected over the column's rows, 0.05): "best" says only what the
// seeds support. A mean over fewer seeds is over other seeds, so it is never the best: such a
// row is bold only where that test supports it, and a row with fewer than
// kFewestSeedsForInference seeds in common with the best is not tested and stays plain.
std::vector<bool> bold_rows(const Column& column, const std::vector<const SummaryRow*>& rows) {
  std::vector<bool> bold(rows.size(), false);
  if (rows.size() < 2) return bold;
  const auto honest = [&](std::size_t r) {
    return column.value(*rows[r]) != nullptr && rows[r]->selection != "test-oracle";
  };
  std::size_t most_seeds = 0;
  for (std::size_t r = 0; r < rows.size(); ++r) {
    if (honest(r)) most_seeds = std::max(most_seeds, column.value(*rows[r])->values.size());
  }
  const auto contends = [&](std::size_t r) { return honest(r) && column.value(*rows[r])->values.size() == most_seeds; };
  std::optional<double> best;
  for (std::size_t r = 0; r < rows.size(); ++r) {
    if (!contends(r)) continue;
    const double shown = std::round(column.value(*rows[r])->mean * 100);
    if (!best || (column.higher_is_better ? shown > *best : shown < *best)) best = shown;
  }
  if (!best) return bold;
  std::size_t leader = rows.size();
  for (std::size_t r = 0; r < rows.size(); ++r) {
    if (!contends(r)) continue;
    bold[r] = std::round(column.value(*rows[r])->mean * 100) == *best;
    if (bold[r] && leader == rows.size()) leader = r;
  }
  std::vector<std::size_t> tested;
  std::vector<double> p;
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const SeedStatistic* value = column.value(*rows[r]);
    if (bold[r] || value == nullptr || rows[r]->selection == "test-oracle") continue;
    const auto [mine, theirs] = paired_values(*rows[r], *value, *rows[leader], *column.value(*rows[leader]));
    if (static_cast<int>(mine.size()) < kFewestSeedsForInference) continue;
    tested.push_back(r);
    p.push_back(paired_t_test_p(mine, theirs));
  }
  const std::vector<double> adjusted = holm_adjusted(p);
  for (std::size_t i = 0; i < tested.size(); ++i) bold[tested[i]] = !(adjusted[i] < 0.05);
  return bold;
}

// mean, or over several seeds "mean ± std", with its 95% confidence interval, clipped to what the
// column can take, from kFewestSeedsForInference seeds; `interval` wraps the bracketed interval.
std::string cell(const SeedStatistic* statistic, const Column& column, bool with_std, const char* plus_minus,
                 const char* interval = "[{:.2f}, {:.2f}]") {
  if (statistic == nullptr) return "";
  if (!with_std) return fmt::format("{:.2f}", statistic->mean);
  // One seed has no spread; "± 0.00" would claim one.
  if (statistic->values.size() < 2) return fmt::format("{:.2f}{}-", statistic->mean, plus_minus);
  std::string text = fmt::format("{:.2f}{}{:.2f}", statistic->mean, plus_minus, statistic->std);
  if (static_cast<int>(statistic->values.size()) < kFewestSeedsForInference) return text;
  return text + " " + fmt::format(fmt::runtime(interval), std::max(column.low, statistic->mean - statistic->ci95),
                                  std::min(column.high, statistic->mean + statistic->ci95));
}

// What the table's bold and brackets mean, for the line under it.
std::string statistics_note(bool with_std) {
  if (!with_std) {
    return "Bold: the best mean. One seed: nothing here separates two methods beyond this run.";
  }
  return fmt::format("Mean ± standard deviation over seeds; in brackets the 95% confidence interval of the mean "
                     "(Student t), clipped to the metric's range, for rows of {0} seeds or more. Bold: the best mean "
                     "and every row a paired t-test across the seeds both ran cannot separate from it (two-sided, "
                     "Holm-corrected over the column, 0.05); the best is taken among the rows of the most seeds, and "
                     "rows of fewer than {0} seeds in common with it are not tested: bold only where they have as many "
                     "seeds and their mean ties it. A row of one seed has no spread (-).", kFewestSeedsForInference);
}

// A row whose base training was still rising, or did not learn, is marked; its footnote says how.
// A row whose method carries a note (our reading of a method without a runnable release) is marked
// with the other mark; its footnote gives the note.
std::string marked_label_suffix(const SummaryRow& row, const char* dagger, const char* double_dagger) {
  return std::string(ended_unfinished(row.training) ? dagger : "") + (row.method_note.empty() ? "" : double_dagger);
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
  out += ",training,method_note\n";
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
      // A spread from one seed, or an interval from fewer than kFewestSeedsForInference, says
      // nothing: left empty.
      const bool spread = row->seeds.size() >= 2;
      const auto std_of = [&](const SeedStatistic& statistic) {
        return spread ? fmt::format(",{:.4f}", statistic.std) : std::string(",");
      };
      out += std_of(row->average_accuracy) + std_of(row->performance_drop) + std_of(row->average_drop_rate);
      for (std::size_t s = 0; s < sessions; ++s) {
        out += s < row->session_accuracy.size() ? std_of(row->session_accuracy[s]) : ",";
      }
      const bool inferred = static_cast<int>(row->seeds.size()) >= kFewestSeedsForInference;
      const auto ci95 = [&](const SeedStatistic& statistic) {
        return inferred ? fmt::format(",{:.4f}", statistic.ci95) : std::string(",");
      };
      out += ci95(row->average_accuracy) + ci95(row->performance_drop) + ci95(row->average_drop_rate);
      for (std::size_t s = 0; s < sessions; ++s) {
        out += s < row->session_accuracy.size() ? ci95(row->session_accuracy[s]) : ",";
      }
    }
    out += fmt::format(",{},{}\n", verdict_name(row->training), csv_field(row->method_note));
  }
  return out;
}

std::string render_latex(const SummaryTable& table, const std::string& what) {
  const bool with_std = table.several_seeds();
  std::string out = "% fscil-bench results; requires \\usepackage{booktabs}\n";
  for (const auto& dataset : table.datasets()) {
    const auto rows = rows_of(table, dataset);
    const auto columns = paper_columns(max_sessions(rows));
    const std::size_t sessions = columns.size() - 3;
    out += "\\begin{table*}[!t]\n\\centering\n";
    // A table travels without its page: the caption says when its data are simulated.
    bool simulated = false;
    const std::string imitated = paper_dataset_of(dataset, &simulated);
    const std::string data = simulated ? fmt::format("{} (simulated, standing in for {})", dataset, imitated) : dataset;
    out += fmt::format("\\caption{{{} on {}, {} split{}{}.}}\n", latex_text(what), latex_text(data), table.evaluated_on,
                       table.title_note(), with_std ? " (mean $\\pm$ std over seeds)" : "");
    const auto grid_keys = table.grid_keys();
    out += fmt::format("\\begin{{tabular}}{{{}l{}ccc}}\n\\toprule\n", std::string(grid_keys.size(), 'l'),
                       std::string(sessions, 'c'));
    // Two header rows, the names on the first (booktabs' layout; no multirow to install).
    for (const auto& key : grid_keys) out += fmt::format("{} & ", latex_text(key));
    out += fmt::format("Method & \\multicolumn{{{}}}{{c}}{{Accuracy in each session $\\uparrow$}}"
                       " & PD$\\downarrow$ & AA$\\uparrow$ & ADR$\\downarrow$ \\\\\n",
                       sessions);
    out += fmt::format("\\cmidrule(lr){{{}-{}}}\n", grid_keys.size() + 2, grid_keys.size() + sessions + 1);
    out += std::string(grid_keys.size() * 2, ' ');
    for (std::size_t k = 0; k < grid_keys.size(); ++k) out += "&";
    for (std::size_t s = 0; s < sessions; ++s) out += fmt::format(" & {}", s);
    out += " & & & \\\\\n\\midrule\n";
    std::vector<std::vector<bool>> bold;
    for (const auto& column : columns) bold.push_back(bold_rows(column, rows));
    for (std::size_t r = 0; r < rows.size(); ++r) {
      const SummaryRow* row = rows[r];
      for (const auto& key : grid_keys) out += latex_text(cell_value(*row, key)) + " & ";
      out += latex_text(row_label(*row)) + marked_label_suffix(*row, "$^\\dagger$", "$^\\ddagger$");
      for (std::size_t c = 0; c < columns.size(); ++c) {
        const std::string text =
            cell(columns[c].value(*row), columns[c], with_std, "$\\pm$", "{{\\scriptsize[{:.2f}, {:.2f}]}}");
        out += bold[c][r] ? fmt::format(" & \\textbf{{{}}}", text) : fmt::format(" & {}", text);
      }
      out += " \\\\\n";
    }
    out += "\\bottomrule\n\\end{tabular}\n";
    out += fmt::format("\\par\\footnotesize {}\n", latex_text(statistics_note(with_std)));
    if (const auto notes = unfinished_notes(rows); !notes.empty()) {
      out += fmt::format("\\par\\footnotesize $^\\dagger$ {}: {}.\n", latex_text(kUnfinishedNote),
                         latex_text(fmt::format("{}", fmt::join(notes, "; "))));
    }
    for (const auto& note : method_notes(rows)) out += fmt::format("\\par\\footnotesize $^\\ddagger$ {}.\n", latex_text(note));
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
    out += fmt::format("### {}, {} split{}{}\n\n|", dataset, table.evaluated_on, table.title_note(),
                       with_std ? " (mean ± std over seeds)" : "");
    for (const auto& key : grid_keys) out += fmt::format(" {} |", key);
    out += " method |";
    for (const auto& column : columns) out += fmt::format(" {} |", column.title);
    out += "\n|";
    for (std::size_t k = 0; k < grid_keys.size(); ++k) out += "---|";
    out += "---|";
    for (std::size_t c = 0; c < columns.size(); ++c) out += "---:|";
    out += "\n";
    std::vector<std::vector<bool>> bold;
    for (const auto& column : columns) bold.push_back(bold_rows(column, rows));
    for (std::size_t r = 0; r < rows.size(); ++r) {
      const SummaryRow* row = rows[r];
      out += "|";
      for (const auto& key : grid_keys) out += fmt::format(" {} |", cell_value(*row, key));
      out += fmt::format(" {}{} |", row_label(*row), marked_label_suffix(*row, " †", " ‡"));
      for (std::size_t c = 0; c < columns.size(); ++c) {
        const std::string text = cell(columns[c].value(*row), columns[c], with_std, " ± ");
        out += bold[c][r] ? fmt::format(" **{}** |", text) : fmt::format(" {} |", text);
      }
      out += "\n";
    }
    out += "\n" + statistics_note(with_std) + "\n\n";
    if (const auto notes = unfinished_notes(rows); !notes.empty()) {
      out += fmt::format("† {}:\n", kUnfinishedNote);
      for (const auto& note : notes) out += fmt::format("- {}\n", note);
      out += "\n";
    }
    for (const auto& note : method_notes(rows)) out += fmt::format("‡ {}\n\n", note);
  }
  return out;
}

}  // namespace fscil
