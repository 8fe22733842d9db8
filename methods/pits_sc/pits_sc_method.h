#pragma once
#include <memory>

#include "methods/common/context_statistics.h"
#include "methods/common/resnet18.h"
#include "methods/common/stage_progress.h"
#include "methods/common/stochastic_classifier.h"
#include "methods/method.h"
#include "methods/method_registry.h"
#include "methods/pits_sc/pits_sc_settings.h"
#include "methods/pits_sc/pseudo_incremental.h"

namespace fscil {

class BestEpoch;

// PITS-SC (Li et al., TASLP 2025) as released in vinceasvp/PITEL-CUSC: pretraining with
// CutMix, pseudo-incremental training on raw-signal mixtures with a stochastic classifier,
// then per session new rows = mean support embedding and a fine-tuning of mu and sigma with
// the encoder frozen. docs/methods.md lists where the code and the paper differ.
// cop-fscil builds on these stages through the protected hooks.
class PitsScMethod : public Method {
 public:
  // Its pretraining, as RunContext::stages shares it: cop-fscil/cpi's pretraining is the same to
  // the bit (CPI acts in the pseudo-incremental episodes), so the two train it once.
  static constexpr const char* kPretrainingStage = "pits-sc pretraining";

  explicit PitsScMethod(const ParameterSet& params);
  void train_base(const SessionData& base, RunContext& context) override;
  void learn_session(const SessionData& support, RunContext& context) override;
  torch::Tensor embed(const torch::Tensor& features) override;
  torch::Tensor classify(const torch::Tensor& embeddings) override;
  ModelCost inference_cost(const InputShape& input) const override;
  MethodState save_state() const override;
  void restore_state(const MethodState& state, RunContext& context) override;

  // For tests: the modules as they stand.
  ResNet18Encoder& encoder() { return encoder_; }
  StochasticClassifier& classifier() { return classifier_; }

 protected:
  // Builds the modules for this protocol; cop-fscil adds its adapter.
  virtual void build_network(RunContext& context);
  virtual std::vector<torch::Tensor> network_parameters() { return encoder_->parameters(); }
  // Trained modules besides the encoder and the classifier (cop-fscil's adapter): a stage's kept
  // epoch restores them too.
  virtual std::vector<torch::nn::Module*> extra_trained_modules() { return {}; }
  // A batch through the network in training mode, `mix` (may be empty: PITS-SC's CutMix) applied
  // right after the input norm, then `probe_rows` (undefined = none) replaced by probes inside
  // the network; cop-fscil adds CPI, PCQA and L_PIC.
  virtual TrainingEmbedding training_embedding(const torch::Tensor& features, const InputNormHook& mix,
                                               const torch::Tensor& probe_rows, RunContext& context);
  // Rows of a pretraining batch of `batch` samples to probe (cop-fscil's CPI during pretraining).
  virtual torch::Tensor pretraining_probe_rows(std::int64_t /*batch*/, RunContext& /*context*/) { return {}; }
  // Each pseudo-incremental episode passes here before its loss; cop-fscil chooses CPI's rows.
  virtual void perturb_episode(PitEpisode& /*episode*/, RunContext& /*context*/) {}
  // True when episodes must leave the batch-norm running statistics as they found them.
  virtual bool episodes_keep_running_statistics() const { return false; }
  // After pseudo-incremental training, before the base rows are reset (cop-fscil may re-estimate
  // the batch-norm statistics on clean base data here).
  virtual void after_pseudo_incremental(const SessionData& /*base*/, RunContext& /*context*/) {}
  // True when this run's pretraining is the shared one (RunContext::stages): under the last epoch
  // only, as a kept epoch spans both stages; cop-fscil adds its conditions.
  virtual bool pretraining_shareable(const RunContext& context) const;
  // The statistics of the maps pretraining trains on, the references CPI's probes start from:
  // PITS-SC records them so that cop-fscil/cpi can continue from its pretraining.
  virtual ContextStatisticBank& context_bank() { return recorded_contexts_; }
  // Base validation accuracy into the run's diagnostics (`base_validation_after_<stage>`) and
  // the progress notes.
  void report_validation(RunContext& context, const std::string& stage);
  // After a session's fine-tuning: how far the classifier rows turned from the class means they
  // started at (the mean cosine of the `old_classes` rows seen before it, and of the new rows), in
  // the diagnostics `old_rows_cosine_to_means` and `new_rows_cosine_to_means`. Rows turning away
  // from their classes is the forgetting that fine-tuning every row on the new shots can cause.
  // Beside them the mean norms of those rows (`old_rows_norm`, `new_rows_norm`) and of the
  // support's embeddings as the classifier sees them (`support_embedding_norm`).
  void record_session_geometry(RunContext& context, std::int64_t old_classes,
                               const torch::Tensor& support_embeddings) const;
  // The first new class must follow the seen ones.
  void check_session_order(const SessionData& support) const;

  const PitsScSettings& settings() const { return settings_; }
  ResNet18Encoder encoder_{nullptr};
  StochasticClassifier classifier_{nullptr};
  torch::Tensor stored_means_;  // seen classes x D, the means each session's update replays
  std::int64_t seen_classes_ = 0;

 private:
  void pretrain(const SessionData& base, BestEpoch& best, RunContext& context);
  // The shared pretraining into the modules and `context`, when RunContext::stages holds it.
  bool take_shared_pretraining(RunContext& context);
  void share_pretraining(RunContext& context);
  void train_pseudo_incremental(const SessionData& base, BestEpoch& best, RunContext& context);
  // The modules a stage's kept epoch (RunContext::selection) is a state of.
  std::vector<torch::nn::Module*> selected_modules();
  // The encoder and classifier under the names a shared stage and kept progress file them by.
  StageModules network_modules();
  // What its base stages keep for a run continued by another process (stage_progress.h): the
  // trained modules, the context statistic bank and the stage's loss means `means`.
  StageKeeping stage_keeping(LossPartMeans& means);
  // Scores the epoch just logged on RunContext::base_selection_data (top-1 over the base classes
  // with the classifier as trained) and keeps it when best; nothing when the last epoch is kept.
  void consider_epoch(BestEpoch& best, const std::string& stage, int epoch, RunContext& context);
  // Base rows of mu = base class-mean embeddings; also stores them as the old-class means.
  void reset_base_rows(const SessionData& base, RunContext& context);

  PitsScSettings settings_;
  ContextStatisticBank recorded_contexts_;
};

// The pits-sc entry; the cop-fscil variants build theirs on its stages, profiles and hints.
MethodEntry pits_sc_entry();
// PITS-SC's stages (MethodEntry::work), its pretraining named `pretraining_stage`: the shared
// stage's name where the run can share it.
std::vector<StageWork> pits_sc_work(const ParameterSet& read, const RunSizes& sizes, const std::string& pretraining_stage);

}  // namespace fscil
