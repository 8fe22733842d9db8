#pragma once
#include <torch/torch.h>

#include <functional>
#include <string>
#include <vector>

#include "methods/common/epoch_validation.h"
#include "methods/common/parameter_snapshot.h"
#include "methods/method.h"

namespace fscil {

// The best epoch of one or more training stages where a run chooses epochs by a score
// (RunContext::selection): every scored epoch that reaches the best score so far (ties go to the
// later epoch, as PITS-SC's reference compares) is snapshotted, and restore() writes it back.
// Stages that share one BestEpoch compete for one slot, as the reference's pretraining and
// pseudo-incremental stage do. The training itself (its steps and random draws) is unchanged.
class BestEpoch {
 public:
  explicit BestEpoch(std::vector<torch::nn::Module*> modules) : modules_(std::move(modules)) {}

  // True when `score` of `epoch` (1-based) of `stage` is kept.
  bool consider(const std::string& stage, int epoch, double score) {
    if (!snapshots_.empty() && score < best_score_) return false;
    snapshots_.clear();
    for (const auto* module : modules_) snapshots_.emplace_back(*module);
    best_score_ = score;
    kept_stage_ = stage;
    kept_epoch_ = epoch;
    return true;
  }

  // Writes the kept state back and records `<stage>_kept_epoch` (0 when an earlier stage's epoch
  // is kept) and `<stage>_selection_score`. Nothing when no epoch was scored.
  void restore(RunContext& context, const std::string& stage) const {
    if (snapshots_.empty()) return;
    for (std::size_t m = 0; m < modules_.size(); ++m) snapshots_[m].restore_into(*modules_[m]);
    context.diagnostics[stage + "_kept_epoch"] = kept_stage_ == stage ? kept_epoch_ : 0;
    context.diagnostics[stage + "_selection_score"] = best_score_;
  }

 private:
  std::vector<torch::nn::Module*> modules_;
  std::vector<ParameterSnapshot> snapshots_;
  double best_score_ = 0;
  std::string kept_stage_;
  int kept_epoch_ = 0;
};

// The epoch's base validation (record_epoch_validation) and, under a selection
// (RunContext::base_selection_data), its "selection_score" on the selection data, which `best`
// considers: base validation's own accuracy where it selects.
inline void score_base_epoch(BestEpoch& best, const std::string& stage, int epoch, RunContext& context,
                             const std::function<torch::Tensor(const SessionData&)>& logits_of,
                             const std::function<SessionData(const SessionData&)>& part = {}) {
  const std::optional<double> validation = record_epoch_validation(context, logits_of, part);
  const SessionData* selection = context.base_selection_data();
  if (selection == nullptr) return;
  const double score = selection == context.validation && validation
                           ? *validation
                           : top1_accuracy(part ? part(*selection) : *selection, logits_of);
  context.training_log.back().values["selection_score"] = score;
  best.consider(stage, epoch, score);
}

}  // namespace fscil
