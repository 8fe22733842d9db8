#pragma once
#include <cstdint>
#include <vector>

#include "methods/amfo/amfo_head.h"
#include "methods/amfo/amfo_loss.h"
#include "methods/amfo/amfo_settings.h"
#include "methods/amfo/fusion_net.h"
#include "methods/common/class_count.h"
#include "methods/common/resnet18.h"
#include "methods/dsn/class_gaussians.h"
#include "methods/dsn/session_supports.h"
#include "methods/method_registry.h"
#include "methods/module_method.h"

namespace fscil {

// AMFO, adaptive mitigation of forgetting and overfitting (Li, Li, Si, Tan, He, IEEE/ACM TASLP
// 2024; Jialongdustin/AMFO, built on DSN's code), on the shared encoder. Two cosine heads over a
// projection fc1: a positive-margin one on the deep embedding and a negative-margin one on the
// pooled first-stage feature, mixed per sample by a small fusion net that also says "base or
// novel". The base session trains all of it. Each session freezes it and, as DSN, adds a gated
// support branch with two heads (one per margin) and a fresh fusion net, trained on the shots and
// on features drawn from every seen class's Gaussian; from then on both heads read the deep
// embedding. Test scores the fused cosines.
class AmfoMethod : public ModuleMethod {
 public:
  explicit AmfoMethod(const ParameterSet& params);
  void train_base(const SessionData& base, RunContext& context) override;
  void learn_session(const SessionData& support, RunContext& context) override;
  // The embedding, then the pooled first-stage feature (D + 64 columns): only the base session's
  // negative head reads the latter.
  torch::Tensor embed(const torch::Tensor& features) override;
  torch::Tensor classify(const torch::Tensor& embeddings) override;
  void restore_state(const MethodState& state, RunContext& context) override;

 protected:
  NamedModules build(const RunContext& context) override;

 private:
  HeadCosines cosines(const torch::Tensor& embeddings, const torch::Tensor& first_stage = {},
                      const torch::Tensor& newest_gate = {});
  // The fused cosines of embed()'s rows over every seen class.
  torch::Tensor fused_cosines(const torch::Tensor& embedded);
  void train_session(const torch::Tensor& shots, const torch::Tensor& shot_labels, std::int64_t first,
                     const torch::Tensor& shot_means, const torch::Tensor& shot_covariances, RunContext& context);
  AmfoLossSettings loss_settings(double fusion, double margin, double binary) const;

  AmfoSettings settings_;
  ResNet18Encoder encoder_{nullptr};
  AmfoHead head_{nullptr};
  SessionSupports supports_{nullptr};
  NegativeHeads negative_heads_{nullptr};
  FusionSlot fusion_{nullptr};
  ClassGaussians gaussians_{nullptr};
  ClassCount seen_classes_{nullptr};
  // What a restore_state() rebuilds before it copies the state in: each session's class count,
  // and the fusion net's classes.
  std::vector<std::int64_t> sessions_to_build_;
  std::int64_t fusion_classes_to_build_ = 0;
};

MethodEntry amfo_entry();

}  // namespace fscil
