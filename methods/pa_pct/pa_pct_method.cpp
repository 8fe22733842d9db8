#include "methods/pa_pct/pa_pct_method.h"

#include <fmt/format.h>

#include <algorithm>

#include "core/random_draws.h"
#include "core/stop_request.h"
#include "methods/common/base_validation.h"
#include "methods/common/best_epoch.h"
#include "methods/common/class_members.h"
#include "methods/common/embedding.h"
#include "methods/common/module_cost.h"
#include "methods/common/session_order.h"
#include "methods/common/supervised_training.h"
#include "methods/common/torch_random_state.h"
#include "methods/pa_pct/pcts_episode.h"
#include "methods/pa_pct/session_attention_step.h"
#include "methods/pan/prototype_query_attention.h"

namespace fscil {

namespace {

// PCTS's episode as PITS-SC's sampler draws it, in PCTS's shape (episode2, cfg L89-L94).
PitsScSettings pcts_episode_settings(const PaPctSettings& settings) {
  PitsScSettings episode;
  episode.pit_way = settings.pcts_way;
  episode.pit_kept = settings.pcts_kept;
  episode.pit_shot = settings.pcts_prototype_shots;
  episode.pit_query = settings.pcts_samples - settings.pcts_prototype_shots;
  episode.pit_alpha = settings.pcts_alpha;
  return episode;
}

// The pseudo-classes an episode of `pairs` forgets: the release's count (5 pairs forget 2); a
// shrunk episode forgets fewer, keeping one, and one of a single pair none, so that it has no
// removal half-step (ours, for tests' tiny protocols).
int forgotten_in(const PaPctSettings& settings, int pairs) {
  return std::max(0, std::min(settings.removal.forgotten, pairs - 1));
}

}  // namespace

PaPctMethod::PaPctMethod(const ParameterSet& params) : PanMethod(params), pa_pct_settings_(PaPctSettings::from(params)) {}

NamedModules PaPctMethod::build(const RunContext& context) {
  NamedModules modules = PanMethod::build(context);
  {
    // Drawn aside from the stream PAN's stages draw from, so that they are pan's to the bit: the
    // two methods share them (PanMethod::kBaseStages).
    const torch::Tensor stream = torch_random_state();
    gated_ = GatedAttention(encoder_->embedding_size());
    restore_torch_random_state(stream);
  }
  gated_->eval();  // its dropouts act only where PCTS and sessions train it
  // slf_attn's copy never trains (fscil_trainer.py L231-L234), whether trained here or restored.
  for (auto& parameter : gated_->settled->parameters()) parameter.requires_grad_(false);
  modules.push_back({"gated_attention", gated_.ptr()});
  return modules;
}

void PaPctMethod::train_base(const SessionData& base, RunContext& context) {
  train_pan_stages(base, context);
  {
    // Both branches start as PAN's attention: slf_attn, frozen, and inc_attn (fscil_trainer.py L231-L234).
    torch::NoGradGuard no_grad;
    for (PanAttention* branch : {&gated_->settled, &gated_->incremental}) {
      const auto from = attention_->parameters(), to = (*branch)->parameters();
      for (std::size_t i = 0; i < from.size(); ++i) to[i].copy_(from[i]);
    }
  }
  train_pcts(base, context);
  // The base rows are the class means again, of the kept encoder (T L282 reloads it, L283 the means).
  const std::int64_t classes = context.base_classes;
  classifier_->set_rows(0, class_means(embed_rows(base.features), base.labels, class_range(0, classes)));
  record_base_validation(*this, context);
}

void PaPctMethod::train_pcts(const SessionData& base, RunContext& context) {
  if (pa_pct_settings_.pcts_epochs == 0) return;
  const PitsScSettings shape_settings = pcts_episode_settings(pa_pct_settings_);
  const PitEpisodeSampler sampler(base, context.base_classes, context.total_classes, shape_settings);
  std::vector<torch::optim::OptimizerParamGroup> groups;
  groups.push_back(episode_group(encoder_parameters(), pa_pct_settings_.pcts_encoder_lr));
  groups.push_back(episode_group(gated_->incremental->parameters(), pa_pct_settings_.pcts_attention_lr));
  groups.push_back(episode_group(gated_->gate->parameters(), pa_pct_settings_.pcts_gate_lr));
  torch::optim::SGD optimizer(std::move(groups), torch::optim::SGDOptions(pa_pct_settings_.pcts_encoder_lr));
  const torch::Tensor base_rows = classifier_->weight().slice(0, 0, context.base_classes).detach().clone();
  const auto embed = [&](const torch::Tensor& features) { return encoder_->forward(features); };
  const AttentionFunction attend = gated_attention();
  PctsRemovalWeights weights = pa_pct_settings_.removal;
  weights.forgotten = forgotten_in(pa_pct_settings_, sampler.shape().pairs);
  const bool removes = weights.forgotten >= 1;
  if (!removes) context.diagnostics["pcts_without_removal"] = 1;
  // Each epoch is scored as the base session would end after it: the rows the class means of the
  // current encoder, through the gated attention. Under a selection, an epoch is kept only if it
  // scores at least what PAN's stages ended at (fscil_trainer.py L240-L250, on its base loader's
  // `val` split, dataloader.py L391-L419; here base validation).
  BestEpoch best({encoder_.get(), gated_.get()});
  const auto logits_of = [&](const SessionData& scored) {
    const torch::Tensor means = class_means(embed_rows(base.features), base.labels, class_range(0, context.base_classes));
    return pqa_logits(attend, means, embed_rows(scored.features), settings_.temperature);
  };
  if (const SessionData* selection = context.base_selection_data()) best.consider("pcts", 0, top1_accuracy(*selection, logits_of));
  const auto train_mode = [&](bool on) {
    encoder_->train(on);  // the release trains PCTS with the whole model in train mode (PCA.py L60)
    gated_->train(on);
  };
  for (int epoch = 0; epoch < pa_pct_settings_.pcts_epochs; ++epoch) {
    train_mode(true);
    double addition_sum = 0, removal_sum = 0;
    for (int e = 0; e < pa_pct_settings_.pcts_episodes; ++e) {
      const PitEpisode episode = sampler.draw(context.generator, context.front_end);
      const PctsAddition addition = pcts_addition(embed, attend, base_rows, context.total_classes, episode,
                                                  sampler.shape(), settings_.temperature);
      optimizer.zero_grad();
      addition.loss.backward();
      optimizer.step();
      addition_sum += addition.loss.item<double>();
      stop_if_requested();
      if (!removes) continue;
      const double lambda = beta(context.generator, pa_pct_settings_.pcts_alpha, pa_pct_settings_.pcts_alpha);
      const PctsRemoval removal = pcts_removal(embed, attend, addition, context.base_classes, base, context.front_end,
                                               episode, sampler.shape(), lambda, settings_.temperature, weights);
      optimizer.zero_grad();
      removal.loss.backward();
      optimizer.step();
      stop_if_requested();
      removal_sum += removal.loss.item<double>();
    }
    const double episodes = pa_pct_settings_.pcts_episodes;
    context.log_epoch("pcts", epoch + 1, pa_pct_settings_.pcts_epochs,
                      {{"loss", (addition_sum + removal_sum) / episodes},
                       {"addition_loss", addition_sum / episodes},
                       {"removal_loss", removal_sum / episodes}});
    train_mode(false);
    score_base_epoch(best, "pcts", epoch + 1, context, logits_of);
    // base_stop=converged ends it as PITS-SC's pseudo-incremental stage ends, its released epochs the cap.
    if (stop_once_levelled_off(settings_.standard, context, "pcts", epoch + 1)) break;
  }
  best.restore(context, "pcts");
}

void PaPctMethod::learn_session(const SessionData& support, RunContext& context) {
  check_session_order(support, seen_classes_->value());  // before anything trains
  {
    const torch::Tensor shots = embed_in_batches(encoder_, support.features).detach();
    std::vector<torch::Tensor> parameters = gated_->incremental->parameters();
    for (const auto& parameter : gated_->gate->parameters()) parameters.push_back(parameter);
    torch::optim::SGD optimizer(parameters, torch::optim::SGDOptions(pa_pct_settings_.session_attention_lr)
                                                .momentum(0.9)
                                                .weight_decay(1e-4));  // CANetwork.py L403-L406
    gated_->incremental->train();  // only inc_attn and the gate train (N L379-L393), in train mode (N L416-L419)
    const torch::Tensor loss =
        session_attention_loss(gated_attention(), shots, support.labels, support.new_classes, settings_.temperature);
    optimizer.zero_grad();
    loss.backward();
    optimizer.step();
    gated_->incremental->eval();
    context.diagnostics["session_attention_loss"] = loss.item<double>();
  }
  PanMethod::learn_session(support, context);
}

void PaPctMethod::forget_classes(const std::vector<std::int64_t>& classes, RunContext& /*context*/) {
  torch::NoGradGuard no_grad;
  for (const std::int64_t cls : classes) classifier_->set_rows(cls, torch::zeros({1, encoder_->embedding_size()}));
}

torch::Tensor PaPctMethod::classify(const torch::Tensor& embeddings) {
  torch::NoGradGuard no_grad;
  const std::int64_t seen = seen_classes_->value();
  return pqa_logits(gated_attention(), classifier_->weight().slice(0, 0, seen), embeddings, settings_.temperature);
}

PaPctMethod::AttentionFunction PaPctMethod::gated_attention() {
  return [this](const torch::Tensor& tokens) { return gated_->forward(tokens); };
}

ModelCost PaPctMethod::inference_cost(const InputShape& input) const {
  ModelCost cost;
  encoder_->count_cost(cost, "encoder", input.feature_map());
  // Both branches of the gated PQA over the seen rows and the sample, the gate on every token,
  // then the cosine logits.
  const std::int64_t tokens = seen_classes_->value() + 1, dim = encoder_->embedding_size();
  count_pqa_cost(cost, "settled_attention", gated_->settled, tokens);
  count_pqa_cost(cost, "incremental_attention", gated_->incremental, tokens);
  LayerCost hidden = layer_with_parameters("gate.hidden", "linear", gated_->gate->children()[0]->parameters());
  hidden.macs = tokens * linear_macs(2 * dim, dim / 2);
  cost.add(std::move(hidden));
  LayerCost out = layer_with_parameters("gate.out", "linear", gated_->gate->children()[2]->parameters());
  out.macs = tokens * linear_macs(dim / 2, 1);
  cost.add(std::move(out));
  LayerCost mix{"gate.mix", "attention"};  // (1 - g) c1 + g c2
  mix.macs = tokens * dim;
  cost.add(std::move(mix));
  count_rows_cost(cost);
  cost.freeze("encoder");
  cost.freeze("settled_attention");  // sessions step inc_attn and the gate, then fine-tune the new rows
  return cost;
}

MethodEntry pa_pct_entry() {
  MethodEntry entry = pan_entry();
  entry.name = "pa-pct";
  entry.summary = "PA-PCT: PAN, then pseudo class-variable training (pseudo-classes added, then two forgotten) of the "
                  "encoder and a gated incremental attention; sessions step the attention, then PAN's rows";
  entry.create = [](const ParameterSet& params) { return std::make_unique<PaPctMethod>(params); };
  entry.base_epoch_keys.push_back("pa_pct_epochs");
  const auto pan_work = entry.work;
  entry.work = [pan_work](const ParameterSet& read, const RunSizes& sizes) {
    std::vector<StageWork> stages = pan_work(read, sizes);  // PAN's shared stages, then its sessions
    const PaPctSettings settings = PaPctSettings::from(read);
    const PitEpisodeShape episode =
        pit_episode_shape(pcts_episode_settings(settings), sizes.base_classes, sizes.total_classes() - sizes.base_classes);
    const int retained = episode.pairs - forgotten_in(settings, episode.pairs);
    // Per episode: the kept and mixed samples trained; the removal half-step's kept and re-mixed
    // samples through the frozen encoder. Each epoch's scoring embeds the base samples for their
    // means and base validation. Under base_stop=converged it stops where such stages typically do.
    SupervisedSchedule pcts_schedule = PanSettings::from(read).standard;
    pcts_schedule.epochs = settings.pcts_epochs;
    const double epochs = pcts_schedule.expected_epochs();
    StageWork pcts{"pcts", epochs * settings.pcts_episodes * (episode.kept + episode.pairs) * episode.per_class()};
    pcts.inferred = epochs * (settings.pcts_episodes * (episode.kept + retained) * episode.per_class() +
                              static_cast<double>(sizes.base_train + sizes.base_validation));
    stages.insert(stages.begin() + 1, pcts);
    return stages;
  };
  entry.session_only_parameters.insert("pa_pct_session_lr");
  // Its own values act only after PAN's stages, which it shares with pan.
  entry.shared_stages[PanMethod::kBaseStages] = {"pa_pct_epochs", "pa_pct_episodes", "pa_pct_alpha",
                                                 "pa_pct_encoder_lr", "pa_pct_attention_lr"};
  // Smoke checks the machinery, not the schedule (ours).
  entry.profile_defaults["smoke"].push_back({"pa_pct_epochs", "1"});
  entry.profile_defaults["smoke"].push_back({"pa_pct_episodes", "2"});
  return entry;
}

}  // namespace fscil
