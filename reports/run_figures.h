#pragma once
#include <string>
#include <vector>

#include "reports/cost_table.h"
#include "reports/figure.h"
#include "reports/run_record.h"
#include "reports/summary_table.h"

namespace fscil {

// Figures drawn from result files. Rows chosen on test carry their label in the legend and the
// figure its note, "selected on test (inflated)".

enum class SessionMetric { all, base, novel, harmonic };

// Accuracy per session of every row of `dataset` (a line per method and sweep cell): on all seen
// classes, on the base or the novel classes, or their harmonic mean. Named sessions_DATASET_METRIC.
Figure session_accuracy_figure(const SummaryTable& table, const std::string& dataset, SessionMetric metric);

// Context-to-class dispersion R per session (mean over seeds), a line per method and cell; no
// figure (empty series) when no run of `dataset` measured it. Named context_ratio_DATASET.
Figure context_ratio_figure(const std::vector<RunRecord>& records, const std::string& dataset);

// The paper's efficiency figure as three bar panels per dataset: FLOPs, parameters (NP) and
// inference time per sample (IT) of each method. Named efficiency_DATASET_{flops,params,it}.
std::vector<Figure> efficiency_figures(const std::vector<CostRow>& costs, const std::string& dataset);

// AA and PD of each row of `dataset` as grouped bars (the paper's ablation figure).
Figure ablation_figure(const SummaryTable& table, const std::string& dataset, const std::string& name);

// A metric ("AA", "PD", "ADR", "Acc0") against the values of sweep key `key` (in `values` order),
// a line per method. Rows whose other keys differ are separate lines.
Figure grid_metric_figure(const SummaryTable& table, const std::string& dataset, const std::string& key,
                          const std::vector<std::string>& values, const std::string& metric, const std::string& name,
                          const std::string& title);

// Mean time per incremental session against the values of `key`, a line per method (N_ps figure).
Figure grid_update_time_figure(const std::vector<CostRow>& costs, const std::string& dataset, const std::string& key,
                               const std::vector<std::string>& values, const std::string& name,
                               const std::string& title);

}  // namespace fscil
