#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "reports/run_record.h"

namespace fscil {

// What one (method, dataset) costs, over its seeds: inference FLOPs and parameters (NP) of the
// final model, inference time per sample (IT), time to train on the base session, time per
// incremental session (prototype update and fine-tuning), peak resident memory and the replay
// memory the method keeps of real old samples.
struct CostRow {
  std::string method;
  std::string dataset;
  GridCell grid;  // the sweep cell (RunRecord::grid); empty outside a sweep
  std::size_t runs = 0;
  double mega_flops = 0;              // per sample, 2 x MACs; largest over seeds
  double parameters_millions = 0;     // all parameters; largest over seeds
  double trainable_millions = 0;     // still trained in incremental sessions
  double inference_ms_per_sample = 0;  // mean over seeds
  double base_train_seconds = 0;    // mean over seeds
  double update_seconds = 0;        // mean over seeds and incremental sessions
  double run_peak_mib = 0;          // run_peak_bytes, largest over seeds
  std::int64_t replay_samples = 0;  // after the last session; largest over seeds
  double replay_mib = 0;
};

// The method, and its sweep cell when it has one: "method [cell]".
std::string cost_row_label(const CostRow& row);

// Rows in order of first appearance of (method, dataset, sweep cell).
std::vector<CostRow> summarize_costs(const std::vector<RunRecord>& records);

std::string render_cost_csv(const std::vector<CostRow>& rows);
std::string render_cost_latex(const std::vector<CostRow>& rows);
std::string render_cost_markdown(const std::vector<CostRow>& rows);

}  // namespace fscil
