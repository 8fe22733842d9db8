#pragma once
#include <torch/torch.h>

#include <map>
#include <string>

#include "methods/common/module_state.h"

namespace fscil {

// A training step's loss in its two parts: the classification loss and a method's side loss
// (cop-fscil's lambda L_PIC; undefined when there is none).
struct LossParts {
  torch::Tensor classification, side;
  torch::Tensor total() const { return side.defined() ? classification + side : classification; }
};

// Mean of each part over a stage's steps, as the run's diagnostics record them.
class LossPartMeans {
 public:
  void add(const LossParts& parts) {
    classification_ += parts.classification.item<double>();
    if (parts.side.defined()) side_ += parts.side.item<double>(), has_side_ = true;
    ++steps_;
  }
  // `<stage>_ce_mean` and, with a side loss, `<stage>_side_loss_mean`.
  void record(std::map<std::string, double>& diagnostics, const std::string& stage) const {
    if (steps_ == 0) return;
    diagnostics[stage + "_ce_mean"] = classification_ / steps_;
    if (has_side_) diagnostics[stage + "_side_loss_mean"] = side_ / steps_;
  }
  // The sums so far into `state` under `key`, and back (a stage continued by another process of
  // its run: stage_progress.h); doubles, so the means come out to the bit.
  void save_into(MethodState& state, const std::string& key) const {
    state[key] = torch::tensor({classification_, side_, static_cast<double>(steps_), has_side_ ? 1.0 : 0.0}, torch::kDouble);
  }
  void restore_from(const MethodState& state, const std::string& key) {
    const torch::Tensor sums = take(state, key).to(torch::kDouble).contiguous();
    if (sums.numel() != 4) throw MethodError("state '" + key + "': expected the 4 sums of a stage's loss means");
    const double* value = sums.data_ptr<double>();
    classification_ = value[0];
    side_ = value[1];
    steps_ = static_cast<int>(value[2]);
    has_side_ = value[3] != 0;
  }
  // `ce` and, with a side loss, `side_loss`: an epoch's terms in the training log.
  void record_terms(std::map<std::string, double>& values) const {
    if (steps_ == 0) return;
    values["ce"] = classification_ / steps_;
    if (has_side_) values["side_loss"] = side_ / steps_;
  }

 private:
  double classification_ = 0, side_ = 0;
  int steps_ = 0;
  bool has_side_ = false;
};

}  // namespace fscil
