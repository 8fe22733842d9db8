#include "methods/prototype/prototype_method.h"

#include <fmt/format.h>

#include "methods/common/embedding.h"
#include "methods/common/module_cost.h"
#include "methods/common/module_state.h"

namespace fscil {

PrototypeMethod::PrototypeMethod(const ParameterSet& params)
    : schedule_(SupervisedSchedule::from(params)), temperature_(params.real("temperature", 16.0, ValidRange::above(0))) {}

void PrototypeMethod::build_network(const RunContext& context) {
  encoder_ = ResNet18Encoder(encoder_options(context));
  classifier_ = CosineClassifier(context.total_classes, encoder_->embedding_size(), temperature_);
}

void PrototypeMethod::train_base(const SessionData& base, RunContext& context) {
  build_network(context);
  train_supervised(encoder_, classifier_, base, context.base_classes, schedule_, context, "base");
  seen_classes_ = 0;
  add_prototypes(base);
  if (context.validation != nullptr && context.progress != nullptr) {
    context.progress->note(fmt::format("base validation accuracy {:.2f}%", accuracy_on(*context.validation)));
  }
}

void PrototypeMethod::learn_session(const SessionData& support, RunContext& context) { add_prototypes(support); }

void PrototypeMethod::add_prototypes(const SessionData& data) {
  const torch::Tensor embeddings = embed_in_batches(encoder_, data.features);
  const torch::Tensor means = normalized_class_means(embeddings, data.labels, data.new_classes);
  if (data.new_classes.front() != seen_classes_) {
    throw MethodError(fmt::format("session {} starts at class {}, expected {}", data.session, data.new_classes.front(),
                                  seen_classes_));
  }
  classifier_->set_rows(seen_classes_, means);
  seen_classes_ += static_cast<std::int64_t>(data.new_classes.size());
}

MethodState PrototypeMethod::save_state() const {
  MethodState state{{"seen_classes", torch::tensor(seen_classes_)}};
  put_module(state, "encoder.", *encoder_);
  put_module(state, "classifier.", *classifier_);
  return state;
}

void PrototypeMethod::restore_state(const MethodState& state, RunContext& context) {
  build_network(context);
  take_module(state, "encoder.", *encoder_);
  take_module(state, "classifier.", *classifier_);
  seen_classes_ = take(state, "seen_classes").item<std::int64_t>();
}

torch::Tensor PrototypeMethod::embed(const torch::Tensor& features) { return embed_in_batches(encoder_, features); }

torch::Tensor PrototypeMethod::classify(const torch::Tensor& embeddings) {
  torch::NoGradGuard no_grad;
  return classifier_->forward(embeddings, seen_classes_);
}

ModelCost PrototypeMethod::inference_cost(const InputShape& input) const {
  ModelCost cost;
  encoder_->count_cost(cost, "encoder", input.feature_map());
  count_cosine_classifier(cost, "classifier", encoder_->embedding_size(), seen_classes_, classifier_->parameters());
  cost.freeze("");  // sessions only append mean embeddings
  return cost;
}

std::unique_ptr<Method> make_prototype_method(const ParameterSet& params) {
  return std::make_unique<PrototypeMethod>(params);
}

}  // namespace fscil
