#include "reports/selection_bias.h"

#include <fmt/format.h>

#include <algorithm>
#include <map>

#include "reports/latex_text.h"

namespace fscil {

namespace {

std::string value(bool present, double number, const char* format = "{:.2f}") {
  return present ? fmt::format(fmt::runtime(format), number) : std::string();
}

std::string gain(const SelectionBiasRow& row, bool against_validation, const char* format = "{:+.2f}") {
  const bool present = row.has_oracle && (against_validation ? row.has_validation : row.has_last);
  return value(present, row.aa_oracle - (against_validation ? row.aa_validation : row.aa_last), format);
}

// The method, and the rest of its sweep cell when it has one.
std::string label_of(const SelectionBiasRow& row) { return row.cell.empty() ? row.method : row.method + " [" + row.cell + "]"; }

}  // namespace

std::vector<SelectionBiasRow> measure_selection_bias(const SummaryTable& table) {
  std::vector<SelectionBiasRow> rows;
  for (const auto& summary : table.rows) {
    const std::string cell = grid_cell_name(without_key(summary.grid, "selection"));
    auto row = std::find_if(rows.begin(), rows.end(), [&](const SelectionBiasRow& r) {
      return r.method == summary.method && r.dataset == summary.dataset && r.cell == cell;
    });
    if (row == rows.end()) {
      row = rows.insert(rows.end(), {summary.method, summary.dataset, cell, "", 0, 0, 0, false, false, false});
    }
    const double aa = summary.average_accuracy.mean;
    if (summary.selection == "last") row->aa_last = aa, row->has_last = true;
    if (summary.selection == "validation") row->aa_validation = aa, row->has_validation = true;
    if (summary.selection == "test-oracle") row->aa_oracle = aa, row->has_oracle = true;
    row->seeds = fmt::format("{}", fmt::join(summary.seeds, " "));
  }
  return rows;
}

std::string render_selection_bias_csv(const std::vector<SelectionBiasRow>& rows) {
  std::string out =
      "method,dataset,cell,seeds,AA_last,AA_validation,AA_test_oracle,gain_over_last,gain_over_validation\n";
  for (const auto& row : rows) {
    out += fmt::format("{},{},{},{},{},{},{},{},{}\n", row.method, row.dataset, row.cell, row.seeds,
                       value(row.has_last, row.aa_last, "{:.4f}"), value(row.has_validation, row.aa_validation, "{:.4f}"),
                       value(row.has_oracle, row.aa_oracle, "{:.4f}"), gain(row, false, "{:.4f}"),
                       gain(row, true, "{:.4f}"));
  }
  return out;
}

std::string render_selection_bias_markdown(const std::vector<SelectionBiasRow>& rows) {
  std::string out = "### Selection bias: AA by how epochs were chosen, and what choosing on test adds\n\n"
                    "| method | dataset | seeds | last epoch | best on validation | best on test (inflated) | "
                    "gain over last | gain over validation |\n|---|---|---|---:|---:|---:|---:|---:|\n";
  for (const auto& row : rows) {
    out += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} |\n", label_of(row), row.dataset, row.seeds,
                       value(row.has_last, row.aa_last), value(row.has_validation, row.aa_validation),
                       value(row.has_oracle, row.aa_oracle), gain(row, false), gain(row, true));
  }
  return out + "\n";
}

std::string render_selection_bias_latex(const std::vector<SelectionBiasRow>& rows) {
  std::string out = "% fscil-bench; requires \\usepackage{booktabs}\n\\begin{table}[!t]\n\\centering\n"
                    "\\caption{AA with the last epoch, the best epoch on validation and the best epoch on test (as "
                    "the reference codes select: inflated), and the AA gained by selecting on test.}\n"
                    "\\begin{tabular}{llcccc}\n\\toprule\nMethod & Dataset & Last & Validation & Test (inflated) & "
                    "Gain \\\\\n\\midrule\n";
  for (const auto& row : rows) {
    out += fmt::format("{} & {} & {} & {} & {} & {} \\\\\n", latex_text(label_of(row)), latex_text(row.dataset),
                       value(row.has_last, row.aa_last), value(row.has_validation, row.aa_validation),
                       value(row.has_oracle, row.aa_oracle), gain(row, false));
  }
  return out + "\\bottomrule\n\\end{tabular}\n\\end{table}\n";
}

}  // namespace fscil
