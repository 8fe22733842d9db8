#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "methods/common/class_count.h"
#include "methods/common/resnet18.h"
#include "methods/dsn/class_gaussians.h"
#include "methods/dsn/dsn_head.h"
#include "methods/dsn/dsn_settings.h"
#include "methods/dsn/session_supports.h"
#include "methods/method_registry.h"
#include "methods/module_method.h"

namespace fscil {

// DSN, the dynamic support network (Yang, Lin, Zhang, Liu, Liang, Ji, Ye, TPAMI 2023; Yang-Bob/DSN), on the
// shared encoder. The base session trains the encoder with fc1 and cosine base rows (train.py),
// then keeps a Gaussian (mean, full covariance) of every base class. Each session freezes all of
// that and adds a support branch (a copy of fc1), gated per node, and a head whose rows start at
// the shots' projected means; only these two train, on the real shots and on features drawn from
// every seen class's Gaussian, with distillation to the network before the session and a penalty
// on the gate (Inc_train.py). Old classes live on as Gaussians only: no sample is kept.
class DsnMethod : public ModuleMethod {
 public:
  explicit DsnMethod(const ParameterSet& params);
  void train_base(const SessionData& base, RunContext& context) override;
  void learn_session(const SessionData& support, RunContext& context) override;
  torch::Tensor embed(const torch::Tensor& features) override;
  torch::Tensor classify(const torch::Tensor& embeddings) override;
  void restore_state(const MethodState& state, RunContext& context) override;

 protected:
  NamedModules build(const RunContext& context) override;

 private:
  torch::Tensor cosines(const torch::Tensor& embeddings, const torch::Tensor& newest_gate = {}) const;
  // Trains the newest session's head and support branch; `first` is its first class.
  void train_session(const torch::Tensor& shots, const torch::Tensor& shot_labels, std::int64_t first,
                     const torch::Tensor& shot_means, const torch::Tensor& shot_covariances, RunContext& context);

  DsnSettings settings_;
  ResNet18Encoder encoder_{nullptr};
  DsnHead head_{nullptr};
  SessionSupports supports_{nullptr};
  ClassGaussians gaussians_{nullptr};
  ClassCount seen_classes_{nullptr};
  // Sessions a restore_state() rebuilds before it copies the state in: each one's class count.
  std::vector<std::int64_t> sessions_to_build_;
};

MethodEntry dsn_entry();

}  // namespace fscil
