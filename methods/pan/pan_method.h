#pragma once
#include <memory>
#include <string>

#include "methods/common/class_count.h"
#include "methods/common/cosine_classifier.h"
#include "methods/common/resnet18.h"
#include "methods/common/shared_stage.h"
#include "methods/method_registry.h"
#include "methods/module_method.h"
#include "methods/pan/pan_attention.h"
#include "methods/pan/pan_settings.h"

namespace fscil {

// PAN, self-attention modified prototypes (Li et al., IEEE TMM 2024; vinceasvp/FCAC, "STDU"), on the
// shared encoder. The base session has three stages (models/STDU/fscil_trainer.py L111-L128 at
// 3ddc7af7):
// (a) "standard" training of the encoder alone on the temporary base classes, the cross-entropy
//     taken over the first channels of the embedding itself (no head);
// (b) pseudo-incremental episodes (temporary base + temporary novel classes) in eval mode, whose
//     prototypes pass with each query through a self-attention (PQA) before cosine scoring;
// (c) standard training again on every base class; the base rows become class means.
// Each session adds the shots' means as rows and fine-tunes the new rows only; every test sample
// is scored by PQA against all seen rows.
class PanMethod : public ModuleMethod {
 public:
  // Its three base stages and the rows after them, which PA-PCT trains alike and so shares
  // (MethodEntry::shared_stages).
  static constexpr const char* kBaseStages = "pan base stages";

  explicit PanMethod(const ParameterSet& params);
  void train_base(const SessionData& base, RunContext& context) override;
  void learn_session(const SessionData& support, RunContext& context) override;
  torch::Tensor embed(const torch::Tensor& features) override;
  torch::Tensor classify(const torch::Tensor& embeddings) override;
  ModelCost inference_cost(const InputShape& input) const override;

 protected:
  NamedModules build(const RunContext& context) override;
  // PA-PCT grows from PAN (methods/pa_pct): its stages, modules and rows are PAN's.
  // The three stages and the base rows, without scoring base validation after them.
  void train_pan_stages(const SessionData& base, RunContext& context);
  std::vector<torch::Tensor> encoder_parameters() const;
  // An episode optimiser's group: SGD Nesterov with the shared momentum and weight decay.
  torch::optim::OptimizerParamGroup episode_group(std::vector<torch::Tensor> parameters, double learning_rate) const;
  // The seen rows' cosine logits in an inference cost.
  void count_rows_cost(ModelCost& cost) const;

 private:
  void train_standard(const SessionData& base, std::int64_t classes, const std::string& stage, RunContext& context);
  // What the shared base stages (kBaseStages) hold.
  StageModules shared_modules();
  void train_pseudo_incremental(const SessionData& base, std::int64_t temporary_base, RunContext& context);

 protected:
  PanSettings settings_;
  ResNet18Encoder encoder_{nullptr};
  CosineClassifier classifier_{nullptr};  // the rows: class means, then the sessions' rows
  PanAttention attention_{nullptr};       // PQA (`slf_attn`)
  // The attention prototypes' module (`transatt_proto`): used in episodes only and never trained
  // (the release writes its output through `.data`), so not part of the model's state.
  PanAttention prototype_attention_{nullptr};
  ClassCount seen_classes_{nullptr};
};

// One pass of `attention` over `tokens` tokens in an inference cost, its layers named `name`.*.
void count_pqa_cost(ModelCost& cost, const std::string& name, const PanAttention& attention, std::int64_t tokens);

MethodEntry pan_entry();

}  // namespace fscil
