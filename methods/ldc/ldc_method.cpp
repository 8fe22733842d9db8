#include "methods/ldc/ldc_method.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "methods/common/base_validation.h"
#include "methods/common/class_members.h"
#include "methods/common/class_statistics.h"
#include "methods/common/embedding.h"
#include "methods/common/module_cost.h"
#include "methods/common/session_order.h"
#include "methods/common/supervised_training.h"
#include "methods/common/torch_random_state.h"
#include "methods/prototype/prototype_method.h"

namespace fscil {

namespace F = torch::nn::functional;

namespace {

// A PCU step (one class's drawn features through the unit's rounds, forward and backward) in the
// head steps plan has rates for: 500 epochs of simtex's 75 base classes took 87 s on one thread
// (2.3 ms a step, a head step 1.68 ms; docs/profiling.md, "ldc").
constexpr double kPcuStepsInHeadSteps = 1.4;

}  // namespace

LdcMethod::LdcMethod(const ParameterSet& params) : settings_(LdcSettings::from(params)) {}

NamedModules LdcMethod::build(const RunContext& context) {
  encoder_ = ResNet18Encoder(encoder_options(context));
  classifier_ = CosineClassifier(context.total_classes, encoder_->embedding_size(), settings_.temperature);
  const std::int64_t dim = encoder_->embedding_size();
  {
    // Drawn aside from the stream the pretraining draws from, so that it is prototype's to the bit:
    // the two methods share it (PrototypeMethod::kPretrainingStage).
    const torch::Tensor stream = torch_random_state();
    calibration_ = CalibrationUnit(dim);
    restore_torch_random_state(stream);
  }
  memory_ = DistributionMemory(context.total_classes, settings_.replay_samples, dim);
  seen_classes_ = ClassCount();
  return {{"encoder", encoder_.ptr()},
          {"classifier", classifier_.ptr()},
          {"calibration_unit", calibration_.ptr()},
          {"memory", memory_.ptr()},
          {"seen_classes", seen_classes_.ptr()}};
}

void LdcMethod::train_base(const SessionData& base, RunContext& context) {
  build_modules(context);
  const std::int64_t classes = context.base_classes;
  // The release trains its base as CEC's cosine classifier does (helper.py base_train, mode ft_cos):
  // prototype's pretraining, which the two share.
  PrototypeMethod::pretrain(encoder_, classifier_, base, settings_.base, context);
  // replace_base_fc (helper.py L11-L49): the base rows become the class means (L43), and the base
  // classes' covariances, averaged, the one covariance every class shares (L35, L45).
  const torch::Tensor raw = embed_in_batches(encoder_, base.features);
  memory_->set_unit_scale(settings_.unit_rms / raw.square().mean().sqrt().item<double>());
  const torch::Tensor embeddings = memory_->to_unit(raw);
  const auto [means, covariances] = class_statistics(embeddings, base.labels, class_range(0, classes));
  classifier_->set_rows(0, means);
  memory_->start_covariance(covariances);
  // The biased distribution of every base class, N(its row, the shared covariance), as the release
  // draws a new class's (Network.py L191-L192): its calibration conv layer_6 never learns (ours,
  // docs/methods.md "ldc").
  const torch::Tensor drawn = memory_->draw(means, settings_.calibration_samples);
  memory_->keep(0, drawn);
  // The real distribution each class's draws are matched to: its first embeddings, of the trained
  // encoder (ours: the release keeps the first features epoch 0 of the base training met).
  std::vector<torch::Tensor> real;
  for (std::int64_t c = 0; c < classes; ++c) {
    const torch::Tensor rows = torch::nonzero(base.labels == c).view(-1);
    real.push_back(embeddings.index_select(0, rows.slice(0, 0, settings_.calibration_samples)));
  }
  train_calibration(drawn, real, context);
  seen_classes_->add(classes);
  record_base_validation(*this, context);
}

void LdcMethod::train_calibration(const torch::Tensor& drawn, const std::vector<torch::Tensor>& real,
                                  RunContext& context) {
  // get_optimizer_rec (inc_trainer.py L46-L53): SGD over the unit's layers, momentum 0.9, dampening 0.9,
  // at ldc_calibration_lr (the release's 0.1 diverges here: docs/methods.md, "ldc").
  torch::optim::SGD optimizer(calibration_->parameters(),
                              torch::optim::SGDOptions(settings_.calibration_lr).momentum(0.9).dampening(0.9));
  for (int epoch = 0; epoch < settings_.calibration_epochs; ++epoch) {
    double total = 0;
    for (std::size_t c = 0; c < real.size(); ++c) {
      // A class with fewer real features than draws pairs only as many (ours: the release's shapes
      // would not match).
      const std::int64_t pairs = real[c].size(0);
      const torch::Tensor loss =
          calibration_loss(calibration_->updates(drawn[c].slice(0, 0, pairs), settings_.calibration_rounds), real[c]);
      optimizer.zero_grad();
      loss.backward();
      optimizer.step();
      total += loss.item<double>();
    }
    context.log_epoch("calibration", epoch + 1, settings_.calibration_epochs,
                      {{"loss", total / static_cast<double>(std::max<std::size_t>(real.size(), 1))}});
  }
}

void LdcMethod::learn_session(const SessionData& support, RunContext& context) {
  const std::int64_t seen = seen_classes_->value();
  check_session_order(support, seen);
  const torch::Tensor shots = embed_rows(support.features);
  // update_fc_avg (Network.py): the shots' means as rows, their covariances folded into the shared
  // one (L189-L190), then a few draws per new class from N(mean, shared covariance) (L191-L192),
  // kept for good.
  const auto [means, covariances] = class_statistics(shots, support.labels, support.new_classes);
  classifier_->set_rows(seen, means);
  memory_->fold_covariances(covariances, context.base_classes);
  memory_->keep(seen, memory_->draw(means, settings_.replay_samples));
  const std::int64_t now_seen = seen + static_cast<std::int64_t>(support.new_classes.size());
  finetune_rows(shots, support.labels, now_seen, context);
  seen_classes_->add(static_cast<std::int64_t>(support.new_classes.size()));
}

void LdcMethod::finetune_rows(const torch::Tensor& shots, const torch::Tensor& shot_labels, std::int64_t seen,
                              RunContext& context) {
  // The shots, then every seen class's kept draws after the PCU's updates, in class order (L214-L226).
  torch::Tensor calibrated;
  {
    torch::NoGradGuard no_grad;
    calibrated = calibration_->updates(memory_->kept_features(seen), settings_.calibration_rounds).back();
  }
  const torch::Tensor features = torch::cat({shots, calibrated});
  const torch::Tensor labels = torch::cat({shot_labels, memory_->kept_labels(seen)});
  // Every seen row trains (fc_cls, optimiser L210-L212): SGD, momentum 0.9, dampening 0.9, no weight
  // decay, over unshuffled batches (L230). The release drops a last partial batch, which its CUB
  // sizes (550 + 50 s samples in batches of 50) never leave; ours keep it (ours: a 5-way protocol's
  // remainder is the newest classes' draws). A removed class's row takes no part (ours).
  torch::Tensor rows = classifier_->weight().slice(0, 0, seen).detach().clone().requires_grad_(true);
  torch::optim::SGD optimizer({rows}, torch::optim::SGDOptions(settings_.session_lr).momentum(0.9).dampening(0.9));
  const std::int64_t batch = settings_.session_batch, samples = features.size(0);
  const std::int64_t batches = (samples + batch - 1) / batch;
  const torch::Tensor inputs = F::normalize(features, F::NormalizeFuncOptions().dim(1));
  const torch::Tensor removed = ~memory_->present(seen);
  for (int epoch = 0; epoch < settings_.session_epochs; ++epoch) {
    double total = 0;
    for (std::int64_t i = 0; i < batches; ++i) {
      const std::int64_t end = std::min(samples, (i + 1) * batch);
      const torch::Tensor logits = (settings_.temperature * inputs.slice(0, i * batch, end)
                                                                .matmul(F::normalize(rows, F::NormalizeFuncOptions().dim(1)).t()))
                                       .masked_fill(removed, -std::numeric_limits<float>::infinity());
      const torch::Tensor loss = F::cross_entropy(logits, labels.slice(0, i * batch, end));
      optimizer.zero_grad();
      loss.backward();
      optimizer.step();
      total += loss.item<double>();
    }
    context.log_epoch("session", epoch + 1, settings_.session_epochs,
                      {{"loss", batches > 0 ? total / static_cast<double>(batches) : 0.0}});
  }
  classifier_->set_rows(0, rows.detach());
}

// Removed classes' draws are replayed no more and their rows take no part in later fine-tuning
// (ours); the runner drops the rows from decisions.
void LdcMethod::forget_classes(const std::vector<std::int64_t>& classes, RunContext& /*context*/) {
  memory_->forget(classes);
}

torch::Tensor LdcMethod::embed(const torch::Tensor& features) {
  return memory_->to_unit(embed_in_batches(encoder_, features));
}

torch::Tensor LdcMethod::classify(const torch::Tensor& embeddings) {
  torch::NoGradGuard no_grad;
  return classifier_->forward(embeddings, seen_classes_->value());
}

// Inference is prototype's: the encoder and the cosine rows (the PCU acts in training only).
ModelCost LdcMethod::inference_cost(const InputShape& input) const {
  ModelCost cost;
  encoder_->count_cost(cost, "encoder", input.feature_map());
  count_cosine_classifier(cost, "classifier", encoder_->embedding_size(), seen_classes_->value(),
                          classifier_->parameters());
  cost.freeze("encoder");  // sessions fine-tune the rows only
  return cost;
}

MethodEntry ldc_entry() {
  MethodEntry entry{"ldc",
                    "LDC (our reading: no runnable release): cosine base with class-mean rows, one shared covariance, a "
                    "calibration unit trained to carry drawn features onto real ones; sessions fine-tune every row on "
                    "the shots and every class's calibrated draws",
                    [](const ParameterSet& params) { return std::make_unique<LdcMethod>(params); }};
  entry.table_note =
      "our reading of LDC: its release cannot run and its paper's text was not at hand, so every gap is ours "
      "(docs/methods.md, section ldc)";
  entry.base_epoch_keys = {"pretrain_epochs"};
  entry.work = [](const ParameterSet& read, const RunSizes& sizes) {
    const LdcSettings ldc = LdcSettings::from(read);
    // One PCU step per base class and epoch, each kPcuStepsInHeadSteps head steps' worth.
    StageWork calibration{"calibration", 0, 0, kPcuStepsInHeadSteps * ldc.calibration_epochs * sizes.base_classes};
    StageWork sessions = session_work(sizes, 0);
    for (int session = 1; session < sizes.sessions; ++session) {
      const double samples = sizes.way * sizes.shot + ldc.replay_samples * (sizes.classes_before(session) + sizes.way);
      sessions.head_steps += ldc.session_epochs * std::ceil(samples / ldc.session_batch);
    }
    return std::vector<StageWork>{PrototypeMethod::pretraining_stage_work(read, sizes), base_embedding_work(sizes),
                                  calibration, sessions};
  };
  entry.profile_defaults =
      pretraining_profiles({{"smoke", {{"ldc_calibration_epochs", "20"}, {"ldc_session_epochs", "30"}}}});
  entry.sessions_keep_embedding = true;  // the encoder is frozen after the base session
  entry.shared_stages[PrototypeMethod::kPretrainingStage] = {
      "ldc_calibration_epochs", "ldc_calibration_lr", "ldc_calibration_rounds", "ldc_calibration_samples", "ldc_unit_rms",
      "ldc_replay_samples",     "ldc_session_epochs", "ldc_session_lr",         "ldc_session_batch"};
  entry.session_only_parameters = {"ldc_session_epochs", "ldc_session_lr", "ldc_session_batch"};
  return entry;
}

}  // namespace fscil
