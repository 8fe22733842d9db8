#include "methods/pits_sc/pits_sc_method.h"

#include <fmt/format.h>

#include <optional>

#include "methods/common/best_epoch.h"
#include "methods/common/class_members.h"
#include "methods/common/embedding.h"
#include "methods/common/module_cost.h"
#include "methods/common/module_state.h"
#include "methods/common/session_order.h"
#include "methods/common/shared_stage.h"
#include "methods/common/mixing.h"
#include "methods/common/running_statistics_guard.h"
#include "methods/common/supervised_training.h"
#include "methods/pits_sc/pseudo_incremental.h"
#include "methods/pits_sc/session_finetune.h"
#include "core/random_draws.h"
#include "core/stop_request.h"

namespace fscil {

namespace F = torch::nn::functional;

PitsScMethod::PitsScMethod(const ParameterSet& params) : settings_(PitsScSettings::from(params)) {}

void PitsScMethod::build_network(RunContext& context) {
  encoder_ = ResNet18Encoder(encoder_options(context));
  classifier_ = StochasticClassifier(context.total_classes, encoder_->embedding_size(), settings_.temperature);
}

TrainingEmbedding PitsScMethod::training_embedding(const torch::Tensor& features, const InputNormHook& mix,
                                                   const torch::Tensor& probe_rows, RunContext& /*context*/) {
  if (probe_rows.defined()) throw MethodError("pits-sc has no probes to replace rows with");
  // Records the map where cop-fscil's CPI acts (after bn0 and the mix), as its probe's bank does.
  return {encoder_->forward(features,
                            [&](const torch::Tensor& map) {
                              const torch::Tensor mixed = mix ? mix(map) : map;
                              recorded_contexts_.push(channel_statistics(mixed));
                              return mixed;
                            }),
          {}};
}

void PitsScMethod::train_base(const SessionData& base, RunContext& context) {
  build_network(context);
  // Under a selection, one best epoch over both stages: the reference keeps a pseudo-incremental
  // epoch only when it scores at least the best pretraining epoch (one max_acc slot,
  // models/pitsc/fscil_trainer.py L91-97, base.py L33 at b4d313ff).
  BestEpoch best(selected_modules());
  if (!take_shared_pretraining(context)) {
    pretrain(base, best, context);
    share_pretraining(context);
  }
  reset_base_rows(base, context);
  report_validation(context, "pretraining");
  train_pseudo_incremental(base, best, context);
  after_pseudo_incremental(base, context);
  reset_base_rows(base, context);
  report_validation(context, "pseudo_incremental");
}

void PitsScMethod::pretrain(const SessionData& base, BestEpoch& best, RunContext& context) {
  encoder_->train();
  classifier_->train();
  std::vector<torch::Tensor> parameters = network_parameters();
  parameters.push_back(classifier_->mu);
  const std::int64_t classes = context.base_classes;
  LossPartMeans means, epoch_means;
  const auto parts_of = [&](const TrainingEmbedding& embedded, torch::Tensor classification) {
    const LossParts parts{std::move(classification), embedded.side_loss};
    means.add(parts);
    epoch_means.add(parts);
    return parts.total();
  };
  const BatchLoss loss = [&](const torch::Tensor& features, const torch::Tensor& labels) {
    if (!bernoulli(context.generator, settings_.p_cutmix)) {
      const TrainingEmbedding embedded =
          training_embedding(features, {}, pretraining_probe_rows(features.size(0), context), context);
      return parts_of(embedded, F::cross_entropy(classifier_->forward(embedded.embedding, classes, false), labels));
    }
    const CutMixPlan plan =
        plan_cutmix(features.size(0), features.size(2), features.size(3), settings_.cutmix_alpha, context.generator);
    // After bn0 (the released placement) bn0's batch statistics are those of the clean batch.
    const bool after_norm = settings_.cutmix_after_input_norm;
    const InputNormHook mix = [&plan](const torch::Tensor& map) { return plan.apply(map); };
    const TrainingEmbedding embedded =
        training_embedding(after_norm ? features : plan.apply(features), after_norm ? mix : InputNormHook{},
                           pretraining_probe_rows(features.size(0), context), context);
    const torch::Tensor logits = classifier_->forward(embedded.embedding, classes, false);
    if (!settings_.cutmix_loss_mixed) return parts_of(embedded, F::cross_entropy(logits, labels));  // released
    const torch::Tensor partner_labels = labels.index_select(0, plan.partners);
    return parts_of(embedded, plan.kept_fraction * F::cross_entropy(logits, labels) +
                                  (1 - plan.kept_fraction) * F::cross_entropy(logits, partner_labels));
  };
  train_epochs(
      parameters, loss, base, settings_.pretrain, context, "pretrain",
      [&](int epoch) {
        epoch_means.record_terms(context.training_log.back().values);
        epoch_means = LossPartMeans();
        consider_epoch(best, "pretraining", epoch, context);
      },
      stage_keeping(means));
  best.restore(context, "pretraining");
  means.record(context.diagnostics, "pretraining");
}

bool PitsScMethod::pretraining_shareable(const RunContext& context) const { return stages_shareable(context); }

StageModules PitsScMethod::network_modules() {
  return {{"encoder.", encoder_.get()}, {"classifier.", classifier_.get()}};
}

bool PitsScMethod::take_shared_pretraining(RunContext& context) {
  if (!pretraining_shareable(context)) return false;
  std::optional<TrainedStage> stage = context.stages->find(kPretrainingStage);
  if (!stage) return false;
  continue_from_stage(*stage, network_modules(), context);
  context_bank().restore_from(stage->state, "context_bank.");
  return true;
}

void PitsScMethod::share_pretraining(RunContext& context) {
  if (!pretraining_shareable(context)) return;
  TrainedStage stage = file_stage(context, network_modules());
  context_bank().save_into(stage.state, "context_bank.");
  context.stages->store(kPretrainingStage, std::move(stage));
}

StageKeeping PitsScMethod::stage_keeping(LossPartMeans& means) {
  StageKeeping keeping;
  keeping.modules = network_modules();
  int extra = 0;
  for (auto* module : extra_trained_modules()) keeping.modules.emplace_back(fmt::format("extra{}.", extra++), module);
  keeping.save_more = [this, &means](MethodState& state) {
    context_bank().save_into(state, "context_bank.");
    means.save_into(state, "loss_means");
  };
  keeping.take_more = [this, &means](const MethodState& state) {
    context_bank().restore_from(state, "context_bank.");
    means.restore_from(state, "loss_means");
  };
  return keeping;
}

std::vector<torch::nn::Module*> PitsScMethod::selected_modules() {
  std::vector<torch::nn::Module*> modules = {encoder_.get(), classifier_.get()};
  for (auto* module : extra_trained_modules()) modules.push_back(module);
  return modules;
}

void PitsScMethod::consider_epoch(BestEpoch& best, const std::string& stage, int epoch, RunContext& context) {
  score_base_epoch(best, stage, epoch, context, [&](const SessionData& data) {
    return classifier_->forward(embed_rows(data.features), context.base_classes, false);
  });
}

void PitsScMethod::train_pseudo_incremental(const SessionData& base, BestEpoch& best, RunContext& context) {
  if (settings_.pit.epochs == 0) return;
  const PitEpisodeSampler sampler(base, context.base_classes, context.total_classes, settings_);
  std::vector<torch::Tensor> parameters = network_parameters();
  for (const auto& parameter : classifier_->parameters()) parameters.push_back(parameter);
  const TrainingEmbedder embedder = [&](const torch::Tensor& features, const torch::Tensor& probe_rows) {
    return training_embedding(features, {}, probe_rows, context);
  };
  LossPartMeans means;
  torch::optim::SGD optimizer = make_schedule_sgd(parameters, settings_.pit);
  encoder_->train();
  classifier_->train();
  const StageKeeping keeping = stage_keeping(means);
  const StageResumption resumed =
      resume_stage("pseudo-incremental", settings_.pit.epochs, keeping, optimizer, context);
  for (int epoch = resumed.epochs_done; !resumed.finished && epoch < settings_.pit.epochs; ++epoch) {
    // Once per epoch: the pseudo-incremental stage decays by epoch (a cosine, too, by epoch).
    set_learning_rate(optimizer, settings_.pit, epoch, 0, 1);
    double loss_sum = 0;
    LossPartMeans epoch_means;
    for (int e = 0; e < settings_.pit_episodes; ++e) {
      PitEpisode episode = sampler.draw(context.generator, context.front_end);
      perturb_episode(episode, context);
      std::optional<RunningStatisticsGuard> keep_statistics;
      if (episodes_keep_running_statistics()) keep_statistics.emplace(*encoder_);
      const LossParts parts = pit_episode_loss(embedder, classifier_, episode, sampler.shape(), context.base_classes,
                                               context.total_classes);
      const torch::Tensor loss = parts.total();
      optimizer.zero_grad();
      loss.backward();
      optimizer.step();
      stop_if_requested();
      means.add(parts);
      epoch_means.add(parts);
      loss_sum += loss.item<double>();
    }
    std::map<std::string, double> values = {{"loss", loss_sum / settings_.pit_episodes},
                                            {"lr", optimizer.param_groups().front().options().get_lr()}};
    epoch_means.record_terms(values);
    context.log_epoch("pseudo-incremental", epoch + 1, settings_.pit.epochs, std::move(values));
    consider_epoch(best, "pseudo_incremental", epoch + 1, context);
    // The same stop as the pretraining's (base_stop=converged), `pit_epochs` its cap.
    const bool ends = stop_once_levelled_off(settings_.pit, context, "pseudo-incremental", epoch + 1) ||
                      epoch + 1 == settings_.pit.epochs;
    keep_stage_progress("pseudo-incremental", keeping, optimizer, {epoch + 1, ends, 0}, context);
    if (ends) break;
  }
  best.restore(context, "pseudo_incremental");
  means.record(context.diagnostics, "pseudo_incremental");
}

void PitsScMethod::reset_base_rows(const SessionData& base, RunContext& context) {
  stored_means_ = class_means(embed_rows(base.features), base.labels, class_range(0, context.base_classes));
  classifier_->set_mu_rows(0, stored_means_);
  classifier_->set_mu_rows(context.base_classes,
                           torch::zeros({context.total_classes - context.base_classes, stored_means_.size(1)}));
  seen_classes_ = context.base_classes;
}

void PitsScMethod::report_validation(RunContext& context, const std::string& stage) {
  if (context.validation == nullptr) return;
  const double accuracy = accuracy_on(*context.validation);
  context.diagnostics["base_validation_after_" + stage] = accuracy;
  if (context.progress != nullptr) {
    context.progress->note(fmt::format("base validation accuracy after {}: {:.2f}%", stage, accuracy));
  }
}

void PitsScMethod::record_session_geometry(RunContext& context, std::int64_t old_classes,
                                           const torch::Tensor& support_embeddings) const {
  torch::NoGradGuard no_grad;
  const torch::Tensor rows = classifier_->mu.narrow(0, 0, seen_classes_).norm(2, 1);
  context.diagnostics["old_rows_norm"] = rows.narrow(0, 0, old_classes).mean().item<double>();
  context.diagnostics["new_rows_norm"] = rows.narrow(0, old_classes, seen_classes_ - old_classes).mean().item<double>();
  context.diagnostics["support_embedding_norm"] = support_embeddings.norm(2, 1).mean().item<double>();
  const torch::Tensor cosine = torch::nn::functional::cosine_similarity(
      classifier_->mu.narrow(0, 0, seen_classes_), stored_means_,
      torch::nn::functional::CosineSimilarityFuncOptions().dim(1));
  context.diagnostics["old_rows_cosine_to_means"] = cosine.narrow(0, 0, old_classes).mean().item<double>();
  context.diagnostics["new_rows_cosine_to_means"] =
      cosine.narrow(0, old_classes, seen_classes_ - old_classes).mean().item<double>();
}

void PitsScMethod::check_session_order(const SessionData& support) const {
  fscil::check_session_order(support, seen_classes_);
}

void PitsScMethod::learn_session(const SessionData& support, RunContext& context) {
  check_session_order(support);
  const std::int64_t old_classes = seen_classes_;
  const torch::Tensor embeddings = embed_rows(support.features);  // encoder and bn0 frozen
  const torch::Tensor new_means = class_means(embeddings, support.labels, support.new_classes);
  classifier_->set_mu_rows(seen_classes_, new_means);
  seen_classes_ += static_cast<std::int64_t>(support.new_classes.size());
  finetune_session_rows(classifier_, embeddings, support.labels, stored_means_, seen_classes_,
                        {settings_.epochs_new, settings_.lr_new, settings_.lamda_proto});
  stored_means_ = torch::cat({stored_means_, new_means});
  record_session_geometry(context, old_classes, embeddings);
}

MethodState PitsScMethod::save_state() const {
  // "seen_classes.count", as every method whose counter is a module names it.
  MethodState state{{"seen_classes.count", torch::tensor(seen_classes_)}, {"stored_means", stored_means_.clone()}};
  put_module(state, "encoder.", *encoder_);
  put_module(state, "classifier.", *classifier_);
  return state;
}

void PitsScMethod::restore_state(const MethodState& state, RunContext& context) {
  build_network(context);
  take_module(state, "encoder.", *encoder_);
  take_module(state, "classifier.", *classifier_);
  stored_means_ = take(state, "stored_means").clone();
  // Checkpoints and cached stages written before the name followed the rule say "seen_classes".
  seen_classes_ = take(state, state.count("seen_classes") > 0 ? "seen_classes" : "seen_classes.count").item<std::int64_t>();
}

torch::Tensor PitsScMethod::embed(const torch::Tensor& features) { return embed_in_batches(encoder_, features); }

torch::Tensor PitsScMethod::classify(const torch::Tensor& embeddings) {
  torch::NoGradGuard no_grad;
  return classifier_->forward(embeddings, seen_classes_, false);
}

ModelCost PitsScMethod::inference_cost(const InputShape& input) const {
  ModelCost cost;
  encoder_->count_cost(cost, "encoder", input.feature_map());
  // Inference uses mu only; sigma is still a parameter the model holds.
  count_cosine_classifier(cost, "classifier", encoder_->embedding_size(), seen_classes_, classifier_->parameters());
  cost.freeze("encoder");  // sessions fine-tune the classifier only
  return cost;
}

std::vector<StageWork> pits_sc_work(const ParameterSet& read, const RunSizes& sizes, const std::string& pretraining_stage) {
  const PitsScSettings settings = PitsScSettings::from(read);
  StageWork pretraining = pretraining_work(read, sizes);
  pretraining.stage = pretraining_stage;
  const PitEpisodeShape episode = pit_episode_shape(settings, sizes.base_classes, sizes.total_classes() - sizes.base_classes);
  const double episode_samples = (episode.kept + episode.pairs) * episode.per_class();
  const double pit_epochs = settings.pit.expected_epochs();
  const StageWork pseudo_incremental{"pseudo-incremental", pit_epochs * settings.pit_episodes * episode_samples,
                                     pit_epochs * sizes.base_validation};
  // Rows and validation after each of the two stages.
  StageWork embeddings = base_embedding_work(sizes);
  embeddings.inferred *= 2;
  return {pretraining, pseudo_incremental, embeddings, session_work(sizes, settings.epochs_new)};
}

MethodEntry pits_sc_entry() {
  MethodEntry entry{"pits-sc", "PITS-SC: CutMix pretraining, pseudo-incremental training on raw-signal mixtures, "
                    "stochastic classifier fine-tuned per session",
                    [](const ParameterSet& params) { return std::make_unique<PitsScMethod>(params); }};
  entry.groups = {"ablation"};
  entry.base_epoch_keys = {"pretrain_epochs", "pit_epochs"};
  entry.work = [](const ParameterSet& read, const RunSizes& sizes) {
    return pits_sc_work(read, sizes, PitsScMethod::kPretrainingStage);
  };
  // Smoke shortens its pseudo-incremental stage and its sessions as it does the pretraining; fast
  // keeps the released pit_epochs as the cap of the stage's stop (base_stop=converged).
  entry.profile_defaults =
      pretraining_profiles({{"smoke", {{"pit_epochs", "1"}, {"pit_episodes", "2"}, {"epochs_new", "20"}}}});
  entry.sessions_keep_embedding = true;  // sessions fine-tune the classifier only
  entry.session_only_parameters = {"epochs_new", "lr_new", "lamda_proto"};
  entry.shared_stages[PitsScMethod::kPretrainingStage] = {"pit_epochs", "pit_lr",   "pit_episodes", "pit_way",
                                                          "pit_kept",   "pit_shot", "pit_query",    "pit_alpha"};
  return entry;
}

}  // namespace fscil
