#pragma once
#include <cstdint>
#include <utility>

#include "methods/arp/arp_settings.h"
#include "methods/arp/refinement_attention.h"
#include "methods/arp/relation_head.h"
#include "methods/common/class_count.h"
#include "methods/common/resnet18.h"
#include "methods/method_registry.h"
#include "methods/module_method.h"

namespace fscil {

// The class rows ARP scores against: the base rows are parameters learned from zero
// (FSCIL_model_define_V1.py L208-L211), each session's rows its shots' mean embeddings.
class ArpRowsImpl : public torch::nn::Module {
 public:
  ArpRowsImpl(std::int64_t classes, std::int64_t dim) : rows(register_parameter("rows", torch::zeros({classes, dim}))) {}
  torch::Tensor rows;
};
TORCH_MODULE(ArpRows);

// ARP, adaptively-refined prototypes (Xie et al., Interspeech 2023; chester-w-xie/APR at 78426ecf,
// method code "SPPR"), on the shared encoder. The base session trains the encoder, the learned
// base rows, the refinement attention and the relation head together: beside each batch an
// episode of way + tasks base classes; in each task `way` of them have their rows replaced by their
// supports' means, every row is refined by the attention, and the batch is scored against the
// refined rows by the relation head. Training stops early on the base-validation loss. Sessions
// add the shots' mean embeddings as rows and train nothing; test scores the plain rows with the
// relation head: the refinement acts in base training only, as released (arp_test_rows=refined
// refines the rows at test as well).
class ArpMethod : public ModuleMethod {
 public:
  explicit ArpMethod(const ParameterSet& params);
  void train_base(const SessionData& base, RunContext& context) override;
  void learn_session(const SessionData& support, RunContext& context) override;
  torch::Tensor embed(const torch::Tensor& features) override;
  torch::Tensor classify(const torch::Tensor& embeddings) override;

 protected:
  NamedModules build(const RunContext& context) override;

 private:
  // The relation head's logits against `rows`, in eval mode.
  torch::Tensor relation_logits(const torch::Tensor& embeddings, const torch::Tensor& rows);
  // Cross-entropy and top-1 accuracy (%) of the plain rows on `validation`'s base classes.
  std::pair<double, double> validation_scores(const SessionData& validation, std::int64_t classes);
  void record_base_scores(RunContext& context);

  ArpSettings settings_;
  ResNet18Encoder encoder_{nullptr};
  ArpRows rows_{nullptr};
  RelationHead relation_{nullptr};
  RefinementAttention attention_{nullptr};  // base training; test too under arp_test_rows=refined
  ClassCount seen_classes_{nullptr};
  ClassCount base_classes_{nullptr};
};

MethodEntry arp_entry();

}  // namespace fscil
