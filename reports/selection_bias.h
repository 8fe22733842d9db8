#pragma once
#include <string>
#include <vector>

#include "reports/summary_table.h"

namespace fscil {

// What choosing epochs on test is worth, per method and dataset: AA with the last epoch, with
// the best on validation and with the best on test (the reference codes' habit), and the AA
// gained by selecting on test over the last epoch (and over validation). Rows of a sweep over
// `selection`, one per method, dataset and the rest of its sweep cell; a row without a last-epoch
// run gets no gain.
struct SelectionBiasRow {
  std::string method, dataset;
  std::string cell;  // the sweep cell's other keys (grid_cell_name), "" when selection is the only one
  std::string seeds;
  double aa_last = 0, aa_validation = 0, aa_oracle = 0;
  bool has_last = false, has_validation = false, has_oracle = false;
};

std::vector<SelectionBiasRow> measure_selection_bias(const SummaryTable& table);
std::string render_selection_bias_csv(const std::vector<SelectionBiasRow>& rows);
std::string render_selection_bias_markdown(const std::vector<SelectionBiasRow>& rows);
std::string render_selection_bias_latex(const std::vector<SelectionBiasRow>& rows);

}  // namespace fscil
