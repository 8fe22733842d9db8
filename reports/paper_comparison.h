#pragma once
#include <string>
#include <vector>

#include "reports/paper_tables.h"
#include "reports/summary_table.h"

namespace fscil {

// Our mean numbers beside the paper's for the same dataset and method, and their difference.
// Simulated datasets stand beside the real one they imitate (simtex: HapTex, simtex-lmt:
// LMT108) and are labelled as simulated; methods the paper does not report are left out.
struct PaperComparisonRow {
  std::string dataset;           // ours
  std::string method;            // ours
  std::string paper_dataset;     // the paper's name of the dataset
  std::string paper_table;       // results_* or ablation_*
  std::string paper_method;      // the row's name there
  bool simulated = false;        // our numbers come from the simulator, not the real data
  std::vector<double> ours, paper;  // acc_0.., PD, AA, ADR (sessions both have)
  std::size_t sessions = 0;
  std::string method_note;          // SummaryRow::method_note: e.g. ours is our reading of the method
};

// The paper's name of the dataset our `dataset` is or imitates ("" when the paper has none), and
// whether ours is simulated.
std::string paper_dataset_of(const std::string& dataset, bool* simulated = nullptr);

std::vector<PaperComparisonRow> compare_with_paper(const SummaryTable& ours, const std::vector<PaperRow>& paper);

// Per compared row three lines: ours, paper, ours - paper.
std::string render_paper_comparison_csv(const std::vector<PaperComparisonRow>& rows);
std::string render_paper_comparison_markdown(const std::vector<PaperComparisonRow>& rows);

}  // namespace fscil
