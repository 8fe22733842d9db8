#include "methods/adbs/adbs_method.h"

#include "methods/common/base_validation.h"
#include "methods/common/best_epoch.h"
#include "methods/common/class_members.h"
#include "methods/common/embedding.h"
#include "methods/common/loss_parts.h"
#include "methods/common/module_cost.h"
#include "methods/common/session_order.h"

namespace fscil {

namespace F = torch::nn::functional;

AdbsMethod::AdbsMethod(const ParameterSet& params) : settings_(AdbsSettings::from(params)) {}

NamedModules AdbsMethod::build(const RunContext& context) {
  encoder_ = ResNet18Encoder(encoder_options(context));
  classifier_ = CosineClassifier(context.total_classes, encoder_->embedding_size(), settings_.temperature);
  boundaries_ = DecisionBoundaries(context.total_classes);
  seen_classes_ = ClassCount();
  return {{"encoder", encoder_.ptr()},
          {"classifier", classifier_.ptr()},
          {"boundaries", boundaries_.ptr()},
          {"seen_classes", seen_classes_.ptr()}};
}

void AdbsMethod::train_base(const SessionData& base, RunContext& context) {
  build_modules(context);
  const std::int64_t classes = context.base_classes;
  // Margins train with the encoder and the rows, weight decay included (one SGD over every
  // parameter: models/adbs/fscil_trainer.py L40-L41).
  std::vector<torch::Tensor> parameters = encoder_->parameters();
  for (const auto& parameter : classifier_->parameters()) parameters.push_back(parameter);
  parameters.push_back(boundaries_->margin);
  encoder_->train();
  classifier_->train();
  LossPartMeans means, epoch_means;
  const BatchLoss loss = [&](const torch::Tensor& features, const torch::Tensor& labels) {
    // Training logits scale by |m_c| as the test does (helper.py L79 calls forward_metric).
    const torch::Tensor logits = boundaries_->scale(classifier_->forward(encoder_->forward(features), classes), classes);
    const LossParts parts{F::cross_entropy(logits, labels),
                          settings_.constraint_weight *
                              inter_class_constraint(boundaries_->margin.slice(0, 0, classes),
                                                     classifier_->weight().slice(0, 0, classes))};
    means.add(parts);
    epoch_means.add(parts);
    return parts.total();
  };
  BestEpoch best({encoder_.get(), classifier_.get(), boundaries_.get()});
  train_epochs(parameters, loss, base, settings_.base, context, "base", [&](int epoch) {
    epoch_means.record_terms(context.training_log.back().values);
    epoch_means = LossPartMeans();
    consider_epoch(best, epoch, context);
  });
  best.restore(context, "base");
  means.record(context.diagnostics, "base");
  // The trained rows give way to the classes' mean embeddings, the margins stay
  // (replace_base_fc, helper.py L114 ff.: plain means of the unnormalised embeddings).
  classifier_->set_rows(0, class_means(embed_rows(base.features), base.labels, class_range(0, classes)));
  seen_classes_->add(classes);
  record_margins(context);
  record_base_validation(*this, context);
}

// The reference keeps the base epoch that scores best on the test split (fscil_trainer.py
// L86-L94), with the trained rows and |m_c|; here only under --selection, on what it names
// (every epoch is scored on base validation for the training verdict).
void AdbsMethod::consider_epoch(BestEpoch& best, int epoch, RunContext& context) {
  const std::int64_t classes = context.base_classes;
  score_base_epoch(best, "base", epoch, context, [&](const SessionData& data) {
    return boundaries_->scale(classifier_->forward(embed_rows(data.features), classes), classes);
  });
}

void AdbsMethod::learn_session(const SessionData& support, RunContext& context) {
  const std::int64_t seen = seen_classes_->value();
  check_session_order(support, seen);
  const std::int64_t now = seen + static_cast<std::int64_t>(support.new_classes.size());
  const torch::Tensor embeddings = embed_in_batches(encoder_, support.features);
  classifier_->set_rows(seen, class_means(embeddings, support.labels, support.new_classes));
  torch::Tensor cosine_logits, rows;
  {
    torch::NoGradGuard no_grad;
    cosine_logits = classifier_->forward(embeddings, now);
    rows = classifier_->weight().slice(0, 0, now).clone();
  }
  // Each new margin starts at the mean of the margins before it (Network.py L92-L94), which is the
  // mean of the earlier classes' for every new class of a session.
  const torch::Tensor old_margins = boundaries_->margin.slice(0, 0, seen).detach();
  const torch::Tensor start = old_margins.mean().expand({now - seen});
  const MarginUpdate update{settings_.session_steps, settings_.session_lr, settings_.constraint_weight};
  const torch::Tensor trained =
      train_new_margins(cosine_logits, support.labels, old_margins, start, rows, update,
                        [&](int step, double cross_entropy, double constraint) {
                          context.log_epoch("session", step, update.steps,
                                            {{"loss", cross_entropy + constraint}, {"ce", cross_entropy},
                                             {"side_loss", constraint}});
                        });
  {
    torch::NoGradGuard no_grad;
    boundaries_->margin.slice(0, seen, now).copy_(trained);
  }
  seen_classes_->add(now - seen);
  record_margins(context);
}

// |m_c| of the base classes (mean, least, largest) and the mean of the classes sessions added: the
// bias between classes that the margins set.
void AdbsMethod::record_margins(RunContext& context) const {
  const std::int64_t base = context.base_classes, seen = seen_classes_->value();
  const torch::Tensor magnitudes = boundaries_->margin.detach().abs();
  const torch::Tensor base_magnitudes = magnitudes.slice(0, 0, base);
  context.diagnostics["margin_base_mean"] = base_magnitudes.mean().item<double>();
  context.diagnostics["margin_base_min"] = base_magnitudes.min().item<double>();
  context.diagnostics["margin_base_max"] = base_magnitudes.max().item<double>();
  if (seen > base) context.diagnostics["margin_novel_mean"] = magnitudes.slice(0, base, seen).mean().item<double>();
}

torch::Tensor AdbsMethod::embed(const torch::Tensor& features) { return embed_in_batches(encoder_, features); }

torch::Tensor AdbsMethod::classify(const torch::Tensor& embeddings) {
  torch::NoGradGuard no_grad;
  const std::int64_t seen = seen_classes_->value();
  return boundaries_->scale(classifier_->forward(embeddings, seen), seen);
}

ModelCost AdbsMethod::inference_cost(const InputShape& input) const {
  ModelCost cost;
  encoder_->count_cost(cost, "encoder", input.feature_map());
  const std::int64_t seen = seen_classes_->value();
  count_cosine_classifier(cost, "classifier", encoder_->embedding_size(), seen, classifier_->parameters());
  LayerCost margins = layer_with_parameters("boundaries", "scale", boundaries_->parameters());
  margins.macs = seen;  // one product per seen class's logit
  cost.add(std::move(margins));
  cost.freeze("encoder");
  cost.freeze("classifier");  // sessions write rows as means and train only margins
  return cost;
}

MethodEntry adbs_entry() {
  MethodEntry entry{"adbs",
                    "ADBS: cosine classifier with a learned margin per class and an inter-class constraint; sessions "
                    "add mean prototypes and train only the new classes' margins",
                    [](const ParameterSet& params) { return std::make_unique<AdbsMethod>(params); }};
  entry.base_epoch_keys = {"pretrain_epochs"};
  entry.work = [](const ParameterSet& read, const RunSizes& sizes) {
    return std::vector<StageWork>{pretraining_work(read, sizes), base_embedding_work(sizes),
                                  session_work(sizes, AdbsSettings::from(read).session_steps)};
  };
  entry.profile_defaults = pretraining_profiles();
  entry.sessions_keep_embedding = true;  // the encoder is frozen after the base session
  entry.session_only_parameters = {"adbs_session_steps", "adbs_session_lr"};
  return entry;
}

}  // namespace fscil
