#include "methods/prototype/prototype_method.h"

#include <fmt/format.h>

#include "methods/common/embedding.h"
#include "methods/common/module_cost.h"
#include "methods/common/session_order.h"
#include "methods/common/shared_stage.h"

namespace fscil {

PrototypeMethod::PrototypeMethod(const ParameterSet& params)
    : schedule_(SupervisedSchedule::from(params)), temperature_(params.real("temperature", 16.0, ValidRange::above(0))) {}

NamedModules PrototypeMethod::build(const RunContext& context) {
  encoder_ = ResNet18Encoder(encoder_options(context));
  classifier_ = CosineClassifier(context.total_classes, encoder_->embedding_size(), temperature_);
  seen_classes_ = ClassCount();
  return {{"encoder", encoder_.ptr()}, {"classifier", classifier_.ptr()}, {"seen_classes", seen_classes_.ptr()}};
}

void PrototypeMethod::train_base(const SessionData& base, RunContext& context) {
  build_modules(context);
  pretrain(encoder_, classifier_, base, schedule_, context);
  add_prototypes(base);
  if (context.validation != nullptr && context.progress != nullptr) {
    context.progress->note(fmt::format("base validation accuracy {:.2f}%", accuracy_on(*context.validation)));
  }
}

void PrototypeMethod::pretrain(ResNet18Encoder& encoder, CosineClassifier& classifier, const SessionData& base,
                               const SupervisedSchedule& schedule, RunContext& context) {
  train_or_take_stage(kPretrainingStage, {{"encoder.", encoder.get()}, {"classifier.", classifier.get()}}, context,
                      [&] { train_supervised(encoder, classifier, base, context.base_classes, schedule, context, "base"); });
}

StageWork PrototypeMethod::pretraining_stage_work(const ParameterSet& read, const RunSizes& sizes) {
  StageWork work = pretraining_work(read, sizes);
  work.stage = kPretrainingStage;  // plan counts it once where ldc runs too
  return work;
}

void PrototypeMethod::learn_session(const SessionData& support, RunContext& context) { add_prototypes(support); }

void PrototypeMethod::add_prototypes(const SessionData& data) {
  const torch::Tensor embeddings = embed_in_batches(encoder_, data.features);
  const torch::Tensor means = normalized_class_means(embeddings, data.labels, data.new_classes);
  const std::int64_t seen = seen_classes_->value();
  check_session_order(data, seen);
  classifier_->set_rows(seen, means);
  seen_classes_->add(static_cast<std::int64_t>(data.new_classes.size()));
}

torch::Tensor PrototypeMethod::embed(const torch::Tensor& features) { return embed_in_batches(encoder_, features); }

torch::Tensor PrototypeMethod::classify(const torch::Tensor& embeddings) {
  torch::NoGradGuard no_grad;
  return classifier_->forward(embeddings, seen_classes_->value());
}

ModelCost PrototypeMethod::inference_cost(const InputShape& input) const {
  ModelCost cost;
  encoder_->count_cost(cost, "encoder", input.feature_map());
  count_cosine_classifier(cost, "classifier", encoder_->embedding_size(), seen_classes_->value(),
                          classifier_->parameters());
  cost.freeze("");  // sessions only append mean embeddings
  return cost;
}

MethodEntry prototype_entry() {
  MethodEntry entry{"prototype", "cosine classifier trained on base classes, frozen encoder, class-mean prototypes",
                    [](const ParameterSet& params) { return std::make_unique<PrototypeMethod>(params); }};
  entry.base_epoch_keys = {"pretrain_epochs"};
  entry.work = [](const ParameterSet& read, const RunSizes& sizes) {
    return std::vector<StageWork>{PrototypeMethod::pretraining_stage_work(read, sizes), base_embedding_work(sizes),
                                  session_work(sizes, 0)};
  };
  entry.profile_defaults = pretraining_profiles();
  entry.sessions_keep_embedding = true;  // sessions only add prototypes
  entry.shared_stages[PrototypeMethod::kPretrainingStage] = {};  // ldc trains it alike
  return entry;
}

}  // namespace fscil
