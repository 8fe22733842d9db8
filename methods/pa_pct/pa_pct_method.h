#pragma once
#include <cstdint>
#include <functional>
#include <vector>

#include "methods/pa_pct/gated_attention.h"
#include "methods/pa_pct/pa_pct_settings.h"
#include "methods/pan/pan_method.h"

namespace fscil {

// PA-PCT (Li, Chen, Li, Huang, Interspeech 2026; cgq2971-afk/FCIAC at 6ccc2082), grown from PAN as
// its release grows from PAN's: PAN's three base stages, then PCTS, pseudo class-variable training
// (fscil_trainer.py L227-L295): episodes whose first half adds five pseudo-classes mixed on the raw
// signal and whose second half forgets two of them, training the encoder, an incremental copy of
// PAN's attention and a gate between the two (methods/pa_pct/pcts_episode.h). Each adding session
// takes one attention step on its shots (session_attention_step.h), then PAN's new rows and update;
// a removing session zeroes the removed classes' rows (CANetwork.py L531-L559). Every sample is
// scored through the gated attention. The release's student is left out: its distillation is
// discarded before any session (docs/compared_methods.md, PA-PCT).
class PaPctMethod : public PanMethod {
 public:
  explicit PaPctMethod(const ParameterSet& params);
  void train_base(const SessionData& base, RunContext& context) override;
  void learn_session(const SessionData& support, RunContext& context) override;
  void forget_classes(const std::vector<std::int64_t>& classes, RunContext& context) override;
  torch::Tensor classify(const torch::Tensor& embeddings) override;
  ModelCost inference_cost(const InputShape& input) const override;

 protected:
  NamedModules build(const RunContext& context) override;

 private:
  using AttentionFunction = std::function<torch::Tensor(const torch::Tensor&)>;
  void train_pcts(const SessionData& base, RunContext& context);
  // Tokens through the gated two-branch PQA, in whatever mode its modules are.
  AttentionFunction gated_attention();

  PaPctSettings pa_pct_settings_;
  GatedAttention gated_{nullptr};
};

MethodEntry pa_pct_entry();

}  // namespace fscil
