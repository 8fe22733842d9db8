#include "methods/comp_fscil/comp_fscil_method.h"

#include "methods/common/base_validation.h"
#include "methods/common/best_epoch.h"
#include "methods/common/damped_momentum_steps.h"
#include "methods/common/embedding.h"
#include "methods/common/session_order.h"
#include "methods/comp_fscil/compositional_heads.h"

namespace fscil {

namespace F = torch::nn::functional;

CompFscilMethod::CompFscilMethod(const ParameterSet& params) : settings_(CompSettings::from(params)) {}

NamedModules CompFscilMethod::build(const RunContext& context) {
  encoder_ = ResNet18Encoder(encoder_options(context));
  {
    // The last map's size on this protocol's input: one primitive per position.
    torch::NoGradGuard no_grad;
    encoder_->eval();
    const torch::Tensor map = encoder_->forward_map(
        torch::zeros({1, context.input.channels, context.input.mel_bins, context.input.frames}));
    encoder_->train();
    map_shape_ = {map.size(1), map.size(2), map.size(3)};
  }
  base_classes_ = context.base_classes;
  base_ = PrototypeSet(base_classes_, map_shape_[0], map_shape_[1], map_shape_[2]);
  novel_ = PrototypeSet(context.total_classes - base_classes_, map_shape_[0], map_shape_[1], map_shape_[2]);
  map_temperature_ = LearnedScale(settings_.map_temperature);
  seen_classes_ = ClassCount();
  return {{"encoder", encoder_.ptr()},
          {"base_prototypes", base_.ptr()},
          {"novel_prototypes", novel_.ptr(), true},
          {"map_temperature", map_temperature_.ptr()},
          {"seen_classes", seen_classes_.ptr()}};
}

void CompFscilMethod::train_base(const SessionData& base, RunContext& context) {
  build_modules(context);
  // One SGD over the encoder, both heads' base prototypes and tau, tau weight-decayed too
  // (fscil_trainer.py L77-L79). The release's optimiser also holds the later classes' rows, which
  // only decay there and which every session overwrites: left out, the same numbers.
  std::vector<torch::Tensor> parameters = encoder_->parameters();
  for (const auto& parameter : base_->parameters()) parameters.push_back(parameter);
  parameters.push_back(map_temperature_->value);
  encoder_->train();
  double vector_sum = 0, map_sum = 0, reuse_sum = 0;
  int steps = 0;
  const BatchLoss loss = [&](const torch::Tensor& features, const torch::Tensor& labels) {
    // helper.py L8-L104: CE of the vector head (training form) and of the CKA head on the powered
    // map, and CE of the unpowered map against the base prototypes rebuilt by primitive reuse.
    const torch::Tensor maps = encoder_->forward_map(features);
    const torch::Tensor pooled = maps.mean({2, 3});
    const torch::Tensor tau = map_temperature_->value;
    const torch::Tensor vector_ce = F::cross_entropy(
        vector_distance_logits(signed_power(pooled, settings_.vector_power), base_->rows, settings_.temperature), labels);
    const torch::Tensor map_ce =
        F::cross_entropy(tau * cka_similarity(signed_power(maps, settings_.map_power), base_->maps), labels);
    torch::Tensor total = settings_.vector_weight * vector_ce + settings_.map_weight * map_ce;
    if (settings_.reuse_weight > 0) {
      const torch::Tensor reuse_ce =
          F::cross_entropy(tau * reuse_similarity(maps, base_->maps, settings_.reuse_tau), labels);
      total = total + settings_.reuse_weight * reuse_ce;
      reuse_sum += reuse_ce.item<double>();
    }
    vector_sum += vector_ce.item<double>();
    map_sum += map_ce.item<double>();
    ++steps;
    return total;
  };
  // The release keeps the base epoch whose replay of every session scores best on the last
  // session's test set (fscil_trainer.py L146-L196); a base session cannot replay sessions it has
  // not seen, so --selection scores the combined heads on the base classes (ours).
  BestEpoch best({encoder_.get(), base_.get(), map_temperature_.get()});
  train_epochs(parameters, loss, base, settings_.base, context, "base", [&](int epoch) {
    auto& values = context.training_log.back().values;
    values["vector_ce"] = vector_sum / std::max(steps, 1);
    values["map_ce"] = map_sum / std::max(steps, 1);
    if (settings_.reuse_weight > 0) values["reuse_ce"] = reuse_sum / std::max(steps, 1);
    values["map_temperature"] = map_temperature_->value.item<double>();
    vector_sum = map_sum = reuse_sum = 0;
    steps = 0;
    score_base_epoch(best, "base", epoch, context, [&](const SessionData& data) {
      return test_logits(embed_maps_in_batches(encoder_, data.features), base_classes_);
    });
  });
  best.restore(context, "base");
  seen_classes_->add(base_classes_);
  context.diagnostics["map_temperature"] = map_temperature_->value.item<double>();
  record_base_validation(*this, context);
}

void CompFscilMethod::learn_session(const SessionData& support, RunContext& context) {
  const std::int64_t seen = seen_classes_->value();
  check_session_order(support, seen);
  const std::int64_t now = seen + static_cast<std::int64_t>(support.new_classes.size());
  // Network.py L184-L347: the new rows start at the shots' mean pooled embedding (unpowered), the
  // new maps at their mean map; then full-batch damped-momentum steps on these alone, with CE of the
  // vector head in its training form without power or temperature (L237-L247) and of the CKA head.
  const torch::Tensor maps = embed_maps_in_batches(encoder_, support.features);
  const torch::Tensor pooled = maps.mean({2, 3}), powered = signed_power(maps, settings_.map_power);
  const torch::Tensor old_rows = rows_of(seen).detach(), old_maps = maps_of(seen).detach();
  const torch::Tensor tau = map_temperature_->value.detach();
  torch::Tensor new_rows = class_means(pooled, support.labels, support.new_classes).requires_grad_(true);
  torch::Tensor new_maps = class_means(maps, support.labels, support.new_classes).requires_grad_(true);
  damped_momentum_steps(
      {new_rows, new_maps}, settings_.session_steps, settings_.session_lr,
      [&] {
        const torch::Tensor vector = vector_distance_logits(pooled, torch::cat({old_rows, new_rows}), 1.0);
        const torch::Tensor map = tau * cka_similarity(powered, torch::cat({old_maps, new_maps}));
        return settings_.vector_weight * F::cross_entropy(vector, support.labels) +
               settings_.map_weight * F::cross_entropy(map, support.labels);
      },
      "comp-fscil session update",
      [&](int step, double loss) { context.log_epoch("session", step, settings_.session_steps, {{"loss", loss}}); });
  {
    torch::NoGradGuard no_grad;
    novel_->rows.slice(0, seen - base_classes_, now - base_classes_).copy_(new_rows);
    novel_->maps.slice(0, seen - base_classes_, now - base_classes_).copy_(new_maps);
  }
  seen_classes_->add(now - seen);
}

torch::Tensor CompFscilMethod::rows_of(std::int64_t classes) const {
  if (classes <= base_classes_) return base_->rows.slice(0, 0, classes);
  return torch::cat({base_->rows, novel_->rows.slice(0, 0, classes - base_classes_)});
}

torch::Tensor CompFscilMethod::maps_of(std::int64_t classes) const {
  if (classes <= base_classes_) return base_->maps.slice(0, 0, classes);
  return torch::cat({base_->maps, novel_->maps.slice(0, 0, classes - base_classes_)});
}

// T cos of the centred, powered pooled embedding and each row, plus tau x CKA of the powered map
// and each class's primitives; with T = 1 the CKA head (0 to tau) decides most samples.
torch::Tensor CompFscilMethod::test_logits(const torch::Tensor& maps, std::int64_t classes) const {
  const torch::Tensor pooled = maps.mean({2, 3});
  return vector_cosine_logits(signed_power(pooled, settings_.vector_power), rows_of(classes), settings_.temperature) +
         map_temperature_->value * cka_similarity(signed_power(maps, settings_.map_power), maps_of(classes));
}

torch::Tensor CompFscilMethod::embed(const torch::Tensor& features) {
  return embed_maps_in_batches(encoder_, features).flatten(1);
}

torch::Tensor CompFscilMethod::classify(const torch::Tensor& embeddings) {
  torch::NoGradGuard no_grad;
  const torch::Tensor maps = embeddings.reshape({embeddings.size(0), map_shape_[0], map_shape_[1], map_shape_[2]});
  return test_logits(maps, seen_classes_->value());
}

MethodEntry comp_fscil_entry() {
  MethodEntry entry{"comp-fscil",
                    "Comp-FSCIL: a vector head plus the CKA similarity of the last map's primitives with each class's, "
                    "a primitive-reuse loss in the base; sessions fine-tune only the new rows and maps",
                    [](const ParameterSet& params) { return std::make_unique<CompFscilMethod>(params); }};
  entry.base_epoch_keys = {"pretrain_epochs"};
  entry.work = [](const ParameterSet& read, const RunSizes& sizes) {
    StageWork validation = base_embedding_work(sizes, 0);  // its rows are trained, not embedded
    return std::vector<StageWork>{pretraining_work(read, sizes), validation,
                                  session_work(sizes, CompSettings::from(read).session_steps)};
  };
  entry.profile_defaults = pretraining_profiles();
  entry.sessions_keep_embedding = true;  // the encoder is frozen after the base session
  entry.session_only_parameters = {"comp_session_steps", "comp_session_lr"};
  return entry;
}

}  // namespace fscil
