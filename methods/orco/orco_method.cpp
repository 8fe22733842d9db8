#include "methods/orco/orco_method.h"

#include <fmt/format.h>

#include <cmath>
#include <optional>

#include "methods/common/cosine_classifier.h"
#include "methods/common/embedding.h"
#include "methods/common/epoch_validation.h"
#include "methods/common/masked_view.h"
#include "methods/common/module_state.h"
#include "methods/common/shuffled_batches.h"
#include "methods/orco/orco_losses.h"
#include "methods/orco/pseudo_targets.h"
#include "core/random_draws.h"
#include "core/stop_request.h"

namespace fscil {

namespace F = torch::nn::functional;

namespace {

// Samples masked and encoded together: bounds the masked copies to one batch.
constexpr std::int64_t kViewBatch = 256;

torch::Tensor unit_rows(const torch::Tensor& x) { return F::normalize(x, F::NormalizeFuncOptions().dim(-1)); }

// Two distinct views per sample, picked at random from the V cached ones: B x 2 x D.
torch::Tensor pick_view_pairs(const torch::Tensor& views, std::mt19937_64& generator) {
  const std::int64_t n = views.size(0), v = views.size(1);
  std::vector<std::int64_t> first(static_cast<std::size_t>(n)), second(static_cast<std::size_t>(n));
  for (std::size_t i = 0; i < first.size(); ++i) {
    first[i] = uniform_int(generator, 0, v - 1);
    second[i] = (first[i] + uniform_int(generator, 1, v - 1)) % v;
  }
  const torch::Tensor index = torch::stack({torch::tensor(first), torch::tensor(second)}, 1);
  return views.gather(1, index.unsqueeze(2).expand({n, 2, views.size(2)}));
}

}  // namespace

OrcoMethod::OrcoMethod(const ParameterSet& params) : settings_(OrcoSettings::from(params)) {}

void OrcoMethod::train_base(const SessionData& base, RunContext& context) {
  base_classes_ = context.base_classes;
  encoder_ = ResNet18Encoder(encoder_options(context));
  projector_ = Projector(encoder_->embedding_size(), settings_.projector_hidden, settings_.projection_size);
  pretrain(base, context);

  targets_ = make_pseudo_targets(context.total_classes, settings_.projection_size, settings_.target_steps,
                                 settings_.target_lr, context.generator);
  target_taken_.assign(static_cast<std::size_t>(context.total_classes), false);
  class_targets_.clear();
  assign_classes(base.features, base.labels, base.new_classes);

  const torch::Tensor views = encoded_views(base.features, context);
  // Contrast against perturbed copies of the free targets, labelled apart from every class.
  const torch::Tensor free_rows = torch::tensor(free_target_rows(), torch::kLong);
  ProjectorObjective objective;
  objective.perturbed_targets = targets_.index_select(0, free_rows);
  objective.perturbed_labels = free_rows + context.total_classes;
  objective.novel_from_class = base_classes_;
  // Phase 2 keeps its last epoch: the paper-era reference scores every epoch on the base test set
  // but never restores the best (Network.py L1147-1148, L1260-1270 at 6608340b82).
  // The projector onto the targets is the base classifier: base validation after each epoch (the
  // encoder is frozen, so its validation embeddings are computed once).
  const bool validated = context.validation != nullptr && context.validation->labels.size(0) > 0;
  const torch::Tensor validation = validated ? embed_in_batches(encoder_, context.validation->features) : torch::Tensor();
  train_projector(views, base.labels, settings_.base, objective, {}, settings_.session_stop, context, "projector",
                  "projector", [&] {
                    record_epoch_validation(context, [&](const SessionData&) {
                      return project(validation).matmul(seen_targets().t());
                    });
                  });
  phase_two_projector_ = ParameterSnapshot(*projector_);
  memory_ = ReplayMemory();
  memory_.keep_base_exemplars(base, base_classes_, settings_.exemplars_per_base_class, settings_.exemplar_source,
                              context.generator);
  if (context.validation != nullptr && context.progress != nullptr) {
    context.progress->note(fmt::format("base validation accuracy {:.2f}%", accuracy_on(*context.validation)));
  }
}

// Phase 1: encoder + projector with cross-entropy on a cosine classifier over the encoder's
// embedding and supervised contrastive loss over two masked views.
void OrcoMethod::pretrain(const SessionData& base, RunContext& context) {
  CosineClassifier classifier(base_classes_, encoder_->embedding_size(), settings_.temperature);
  std::vector<torch::Tensor> parameters = encoder_->parameters();
  for (const auto& parameter : projector_->parameters()) parameters.push_back(parameter);
  for (const auto& parameter : classifier->parameters()) parameters.push_back(parameter);
  encoder_->train();
  const BatchLoss loss = [&](const torch::Tensor& features, const torch::Tensor& labels) {
    const torch::Tensor both = torch::cat(
        {masked_view(features, settings_.mask_time_fraction, settings_.mask_mel_fraction, context.generator),
         masked_view(features, settings_.mask_time_fraction, settings_.mask_mel_fraction, context.generator)});
    const torch::Tensor encodings = encoder_->forward(both);
    const std::int64_t n = features.size(0);
    const torch::Tensor projections = project(encodings).view({2, n, -1}).transpose(0, 1);
    return F::cross_entropy(classifier->forward(encodings, base_classes_), labels.repeat({2})) +
           supervised_contrastive_loss(projections, labels, settings_.supcon_temperature);
  };
  train_epochs(parameters, loss, base, settings_.pretrain, context, "pretrain", [&](int) {
    record_epoch_validation(context, [&](const SessionData& scored) {
      return classifier->forward(embed_in_batches(encoder_, scored.features), base_classes_);
    });
  });
  encoder_->eval();
}

torch::Tensor OrcoMethod::encoded_views(const SampleRows& features, RunContext& context) {
  std::vector<torch::Tensor> views;
  for (int v = 0; v < settings_.views; ++v) {
    views.push_back(map_batches(features, kViewBatch, [&](const torch::Tensor& batch) {
      return embed_in_batches(encoder_, masked_view(batch, settings_.mask_time_fraction, settings_.mask_mel_fraction,
                                                    context.generator));
    }));
  }
  return torch::stack(views, 1);
}

torch::Tensor OrcoMethod::project(const torch::Tensor& encodings) { return unit_rows(projector_->forward(encodings)); }

void OrcoMethod::assign_classes(const SampleRows& features, const torch::Tensor& labels,
                                const std::vector<std::int64_t>& classes) {
  if (classes.front() != static_cast<std::int64_t>(class_targets_.size())) {
    throw MethodError(fmt::format("classes start at {}, expected {}", classes.front(), class_targets_.size()));
  }
  torch::Tensor means;
  {
    torch::NoGradGuard no_grad;
    means = class_means(project(embed_in_batches(encoder_, features)), labels, classes);
  }
  const std::vector<std::int64_t> free_targets = free_target_rows();
  if (free_targets.size() < classes.size()) {
    throw MethodError(fmt::format("{} new classes but only {} free pseudo-targets", classes.size(), free_targets.size()));
  }
  for (std::int64_t target : assign_to_targets(means, targets_, free_targets)) {
    target_taken_[static_cast<std::size_t>(target)] = true;
    class_targets_.push_back(target);
  }
}

torch::Tensor OrcoMethod::seen_targets() const { return targets_.index_select(0, torch::tensor(class_targets_)); }

std::vector<std::int64_t> OrcoMethod::free_target_rows() const {
  std::vector<std::int64_t> rows;
  for (std::size_t t = 0; t < target_taken_.size(); ++t) {
    if (!target_taken_[t]) rows.push_back(static_cast<std::int64_t>(t));
  }
  return rows;
}

torch::Tensor OrcoMethod::unassigned_targets() const {
  const std::vector<std::int64_t> rows = free_target_rows();
  if (rows.empty()) return torch::zeros({0, targets_.size(1)});
  return targets_.index_select(0, torch::tensor(rows));
}

void OrcoMethod::train_projector(const torch::Tensor& views, const torch::Tensor& labels,
                                 const ProjectorSchedule& schedule, const ProjectorObjective& objective,
                                 const std::function<double()>& score, const SessionStop& stop,
                                 RunContext& context, const std::string& phase, const std::string& kept,
                                 const std::function<void()>& after_epoch) {
  const torch::Tensor assigned = seen_targets();
  const torch::Tensor assigned_labels = torch::arange(assigned.size(0), torch::kLong);
  const torch::Tensor unassigned = unassigned_targets();
  torch::optim::SGD optimizer(projector_->parameters(), torch::optim::SGDOptions(schedule.learning_rate)
                                                            .momentum(schedule.momentum)
                                                            .dampening(schedule.dampening)
                                                            .weight_decay(schedule.weight_decay));
  const std::int64_t samples = views.size(0);
  std::optional<ParameterSnapshot> best;
  double best_score = -1;
  int epochs_trained = 0, checks_since_best = 0;
  for (int epoch = 0; epoch < schedule.epochs; ++epoch) {
    const double rate = schedule.rate_at(epoch);
    for (auto& group : optimizer.param_groups()) static_cast<torch::optim::SGDOptions&>(group.options()).lr(rate);
    double loss_sum = 0;
    int batches = 0;
    for (const torch::Tensor& index : shuffled_batches(samples, schedule.batch_size, context.generator)) {
      const std::int64_t size = index.size(0);
      const torch::Tensor batch_labels = labels.index_select(0, index);
      const torch::Tensor pairs = pick_view_pairs(views.index_select(0, index), context.generator);
      const torch::Tensor projections = project(pairs.flatten(0, 1)).view({size, 2, -1});
      torch::Tensor contrast = projections, contrast_labels = batch_labels;
      if (objective.perturbed_targets.size(0) > 0) {
        const PerturbedTargets perturbed =
            perturb_targets(objective.perturbed_targets, objective.perturbed_labels, size, settings_.perturb_epsilon,
                            settings_.perturb_offset, context.generator);
        contrast = torch::cat({projections, perturbed.views});
        contrast_labels = torch::cat({batch_labels, perturbed.labels});
      }
      const torch::Tensor logits = projections.transpose(0, 1).flatten(0, 1).matmul(assigned.t());
      const torch::Tensor loss =
          supervised_contrastive_loss(contrast, contrast_labels, settings_.supcon_temperature) +
          orthogonality_loss_from(objective.orthogonality_from_class, projections.select(1, 0), batch_labels,
                                  assigned, assigned_labels, unassigned) +
          split_cross_entropy(logits, batch_labels.repeat({2}), objective.novel_from_class, objective.base_ce_weight,
                              objective.novel_ce_weight);
      optimizer.zero_grad();
      loss.backward();
      optimizer.step();
      stop_if_requested();
      loss_sum += loss.item<double>();
      ++batches;
    }
    context.log_epoch(phase, epoch + 1, schedule.epochs, {{"loss", loss_sum / batches}, {"lr", rate}});
    if (after_epoch) after_epoch();
    epochs_trained = epoch + 1;
    const bool may_stop = schedule.levelled_off_stop_from > 0 && epochs_trained >= schedule.levelled_off_stop_from;
    if (stop_once_levelled_off(may_stop, context, phase, epochs_trained)) break;
    const bool check = (epochs_trained - stop.first_check) % stop.check_every == 0 ||
                       (stop.check_last && epochs_trained == schedule.epochs);
    if (!score || !check) continue;
    const double value = score();
    context.training_log.back().values["selection_score"] = value;
    if (value > best_score) {
      best_score = value;
      best = ParameterSnapshot(*projector_);
      context.diagnostics[kept + "_kept_epoch"] = epochs_trained;
      checks_since_best = 0;
    } else if (++checks_since_best >= stop.patience) {
      break;
    }
  }
  if (!score) return;
  context.diagnostics[kept + "_epochs_trained"] = epochs_trained;
  if (best) {
    best->restore_into(*projector_);
    context.diagnostics[kept + "_stop_score"] = best_score;
  }
}

double OrcoMethod::accuracy_of(const torch::Tensor& encodings, const torch::Tensor& labels) {
  torch::NoGradGuard no_grad;
  const torch::Tensor predicted = project(encodings).matmul(seen_targets().t()).argmax(1);
  return 100.0 * predicted.eq(labels).to(torch::kDouble).mean().item<double>();
}

double OrcoMethod::harmonic_mean_of(const torch::Tensor& encodings, const torch::Tensor& labels) {
  const torch::Tensor is_base = labels < base_classes_;
  const double base = accuracy_of(encodings.index({is_base}), labels.index({is_base}));
  const torch::Tensor is_novel = is_base.logical_not();
  if (is_novel.sum().item<std::int64_t>() == 0) return base;
  const double novel = accuracy_of(encodings.index({is_novel}), labels.index({is_novel}));
  return base + novel > 0 ? 2 * base * novel / (base + novel) : 0.0;
}

void OrcoMethod::learn_session(const SessionData& support, RunContext& context) {
  phase_two_projector_.restore_into(*projector_);
  assign_classes(support.features, support.labels, support.new_classes);
  memory_.keep_all(support.features.all(), support.labels);

  // Contrast against perturbed copies of the incremental classes' targets and of the free ones.
  std::vector<std::int64_t> rows, labels;
  for (std::size_t c = static_cast<std::size_t>(base_classes_); c < class_targets_.size(); ++c) {
    rows.push_back(class_targets_[c]);
    labels.push_back(static_cast<std::int64_t>(c));
  }
  for (std::int64_t row : free_target_rows()) {
    rows.push_back(row);
    labels.push_back(context.total_classes + row);
  }
  ProjectorObjective objective;
  objective.perturbed_targets = targets_.index_select(0, torch::tensor(rows));
  objective.perturbed_labels = torch::tensor(labels);
  objective.novel_from_class = base_classes_;
  objective.base_ce_weight = settings_.base_ce_weight;
  objective.novel_ce_weight = settings_.novel_ce_weight;
  objective.orthogonality_from_class = settings_.session_orthogonality_novel_only ? base_classes_ : 0;

  // The paper-era reference keeps the projector of the best test-set harmonic mean, checked after
  // epochs 1, 6, 11, ... and stopping after 16 checks without a better one (Network.py L1630-1683,
  // train.py L109/L183/L230 at 6608340b82): what --selection test-oracle does. Otherwise
  // orco_session_stop's rule, on the same schedule, scored on base validation and the session's shots.
  std::function<double()> score;
  SessionStop stop = settings_.session_stop;
  if (context.selection == EpochSelection::test_oracle) {
    const torch::Tensor test = embed_in_batches(encoder_, context.oracle_test->features);
    const torch::Tensor test_labels = context.oracle_test->labels;
    score = [this, test, test_labels] { return harmonic_mean_of(test, test_labels); };
    stop = SessionStop{};
  } else if (settings_.session_stop.on_validation || context.selection == EpochSelection::validation) {
    if (context.validation == nullptr || context.validation->labels.size(0) == 0) {
      throw MethodError("orco_session_stop=validation needs a non-empty base validation split; use "
                        "orco_session_stop=last");
    }
    // The encoder is frozen: its embeddings of the validation split and of the shots are fixed.
    const torch::Tensor validation = embed_in_batches(encoder_, context.validation->features);
    const torch::Tensor shots = embed_in_batches(encoder_, support.features);
    const torch::Tensor validation_labels = context.validation->labels, shot_labels = support.labels;
    score = [this, validation, shots, validation_labels, shot_labels] {
      const double base = accuracy_of(validation, validation_labels), novel = accuracy_of(shots, shot_labels);
      return base + novel > 0 ? 2 * base * novel / (base + novel) : 0.0;
    };
  }
  train_projector(encoded_views(memory_.features(), context), memory_.labels(), settings_.session, objective, score,
                  stop, context, fmt::format("session {}", support.session), "session");
}

MethodState OrcoMethod::save_state() const {
  std::vector<std::uint8_t> taken(target_taken_.begin(), target_taken_.end());
  MethodState state{{"base_classes", torch::tensor(base_classes_)},
                    {"targets", targets_.clone()},
                    {"class_targets", torch::tensor(class_targets_, torch::kLong)},
                    {"target_taken", torch::tensor(std::vector<std::int64_t>(taken.begin(), taken.end()), torch::kLong)},
                    {"memory_features", memory_.features().clone()},
                    {"memory_labels", memory_.labels().clone()}};
  put_module(state, "encoder.", *encoder_);
  put_module(state, "projector.", *projector_);
  for (const auto& [name, tensor] : phase_two_projector_.tensors()) state["phase_two_projector." + name] = tensor.clone();
  return state;
}

void OrcoMethod::restore_state(const MethodState& state, RunContext& context) {
  base_classes_ = take(state, "base_classes").item<std::int64_t>();
  encoder_ = ResNet18Encoder(encoder_options(context));
  projector_ = Projector(encoder_->embedding_size(), settings_.projector_hidden, settings_.projection_size);
  take_module(state, "phase_two_projector.", *projector_);
  phase_two_projector_ = ParameterSnapshot(*projector_);
  take_module(state, "encoder.", *encoder_);
  take_module(state, "projector.", *projector_);
  encoder_->eval();
  targets_ = take(state, "targets").clone();
  const torch::Tensor class_targets = take(state, "class_targets").contiguous();
  class_targets_.assign(class_targets.data_ptr<std::int64_t>(), class_targets.data_ptr<std::int64_t>() + class_targets.numel());
  const torch::Tensor taken = take(state, "target_taken").contiguous();
  target_taken_.assign(taken.data_ptr<std::int64_t>(), taken.data_ptr<std::int64_t>() + taken.numel());
  memory_ = ReplayMemory();
  memory_.keep_all(take(state, "memory_features"), take(state, "memory_labels"));
}

torch::Tensor OrcoMethod::embed(const torch::Tensor& features) {
  torch::NoGradGuard no_grad;
  return project(embed_in_batches(encoder_, features));
}

torch::Tensor OrcoMethod::classify(const torch::Tensor& embeddings) {
  torch::NoGradGuard no_grad;
  return embeddings.matmul(seen_targets().t());
}

ModelCost OrcoMethod::inference_cost(const InputShape& input) const {
  ModelCost cost;
  encoder_->count_cost(cost, "encoder", input.feature_map());
  const std::int64_t projection = projector_->count_cost(cost, "projector");
  // Logits are dot products with fixed unit targets: no learnt parameters.
  count_cosine_classifier(cost, "targets", projection, static_cast<std::int64_t>(class_targets_.size()), {});
  cost.freeze("encoder");  // sessions retrain the projector only
  return cost;
}

MethodEntry orco_entry() {
  MethodEntry entry{"orco", "OrCo-style: pseudo-targets, Hungarian assignment, projector trained with SupCon, "
                    "orthogonality and CE; replays 5 exemplars per base class and every earlier shot",
                    [](const ParameterSet& params) { return std::make_unique<OrcoMethod>(params); }};
  entry.base_epoch_keys = {"pretrain_epochs", "orco_base_epochs"};
  entry.work = [](const ParameterSet& read, const RunSizes& sizes) {
    const OrcoSettings orco = OrcoSettings::from(read);
    const double n = static_cast<double>(sizes.base_train), shots = static_cast<double>(sizes.way) * sizes.shot;
    StageWork pretraining = pretraining_work(read, sizes);
    pretraining.trained *= 2;  // two masked views of every sample
    // A projector step (D -> 2048 -> 128 on two cached views of each sample, SupCon, orthogonality)
    // costs about 7 calibrated head steps: fitted on simtex, fast, seed 1 (docs/profiling.md).
    constexpr double kProjectorStep = 7;
    // Assignment, the cached views and validation; then the projector alone on the cached views.
    // Under base_stop=converged the phase has stopped at or soon after its least epochs: count those.
    const int projector_epochs = orco.base.levelled_off_stop_from > 0 ? orco.base.levelled_off_stop_from : orco.base.epochs;
    StageWork projector{"projector", 0, n + orco.views * n + static_cast<double>(sizes.base_validation),
                        kProjectorStep * projector_epochs * std::ceil(n / orco.base.batch_size)};
    StageWork sessions{"sessions", 0, 0, 0, false};
    for (int session = 1; session < sizes.sessions; ++session) {
      const double memory = orco.exemplars_per_base_class * sizes.base_classes + session * shots;
      sessions.inferred += 2 * shots + static_cast<double>(sizes.base_validation) + orco.views * memory;
      sessions.head_steps += kProjectorStep * orco.session.epochs * std::ceil(memory / orco.session.batch_size);
    }
    return std::vector<StageWork>{pretraining, projector, sessions};
  };
  // In smoke, the projector stage shortened as PITS-SC's second stage is (10 epochs: 1) and its
  // sessions as PITS-SC's are (a tenth: 10 epochs, 1 of warm-up). Fast keeps at least the
  // projector's 10 epochs: they are the only ones that map it onto the targets (cut to 2, AA fell
  // 78.62 -> 63.67); its base_stop=converged runs the phase on until it levels off.
  entry.profile_defaults = pretraining_profiles(
      {{"smoke", {{"orco_base_epochs", "1"}, {"orco_session_epochs", "10"}, {"orco_session_warmup", "1"}}}});
  entry.session_only_parameters = {"orco_session_epochs", "orco_session_lr",       "orco_session_batch",
                                   "orco_session_warmup", "orco_session_stop",     "orco_session_check",
                                   "orco_session_patience", "orco_novel_ce_weight", "orco_base_ce_weight",
                                   "orco_session_orthogonality"};
  entry.base_ignores_selection = true;  // phase 2 keeps its last epoch
  return entry;
}

}  // namespace fscil
