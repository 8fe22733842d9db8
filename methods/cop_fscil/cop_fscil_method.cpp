#include "methods/cop_fscil/cop_fscil_method.h"

#include <cmath>
#include <numeric>

#include "methods/common/batch_norm_statistics.h"
#include "methods/common/embedding.h"
#include "methods/common/module_state.h"
#include "methods/common/running_statistics_guard.h"
#include "methods/common/torch_random_state.h"
#include "methods/cop_fscil/stability_calibration.h"
#include "methods/pits_sc/session_finetune.h"
#include "core/seeded_shuffle.h"

namespace fscil {

CopFscilMethod::CopFscilMethod(const ParameterSet& params, CopFscilComponents components)
    : PitsScMethod(params),
      cop_settings_(CopFscilSettings::from(params)),
      components_(components),
      probe_(cop_settings_.cpi) {}

void CopFscilMethod::build_network(RunContext& context) {
  PitsScMethod::build_network(context);
  if (!components_.pcqa) return;
  const std::int64_t dim = encoder_->embedding_size();
  adapter_ = QuotientAdapter(
      QuotientAdapterOptions{dim, cop_settings_.reflections, dim - cop_settings_.sensitive_dim_for(dim),
                             cop_settings_.hidden});
}

std::vector<torch::Tensor> CopFscilMethod::network_parameters() {
  std::vector<torch::Tensor> parameters = PitsScMethod::network_parameters();
  if (components_.pcqa) {
    for (const auto& parameter : adapter_->parameters()) parameters.push_back(parameter);
  }
  return parameters;
}

std::vector<torch::nn::Module*> CopFscilMethod::extra_trained_modules() {
  if (!components_.pcqa) return {};
  return {adapter_.get()};
}

torch::Tensor CopFscilMethod::encode(const torch::Tensor& features, const InputNormHook& mix,
                                     const InputNormHook& probe) {
  if (cop_settings_.cpi.space == ProbeSpace::raw) return encoder_->forward(probe ? probe(features) : features, mix);
  if (!mix || !probe) return encoder_->forward(features, mix ? mix : probe);
  return encoder_->forward(features, [&](const torch::Tensor& map) { return probe(mix(map)); });
}

torch::Tensor CopFscilMethod::encode_for_inference(const torch::Tensor& features, const InputNormHook& probe) {
  if (probe && cop_settings_.cpi.space == ProbeSpace::raw) {
    torch::NoGradGuard no_grad;
    return embed_in_batches(encoder_, probe(features));
  }
  return embed_in_batches(encoder_, features, 256, probe);
}

TrainingEmbedding CopFscilMethod::training_embedding(const torch::Tensor& features, const InputNormHook& mix,
                                                     const torch::Tensor& probe_rows, RunContext& context) {
  // The batch's own probes (the rows CPI replaces) are drawn once, where CPI acts, by the first
  // forward that reaches that map; the clean map's statistics join the bank just before, so the
  // bank only ever holds real samples. L_PIC's probe forwards see the same map as the original.
  bool drawn = false;
  torch::Tensor batch_probes;  // undefined when no row is probed
  const auto probed = [&](const torch::Tensor& map) {
    if (!drawn) {
      drawn = true;
      probe_.observe(map);
      if (probe_rows.defined() && probe_rows.numel() > 0) {
        batch_probes = probe_.intervene(map.index_select(0, probe_rows), context.generator);
      }
    }
    return batch_probes.defined() ? map.index_copy(0, probe_rows, batch_probes) : map;
  };

  const bool with_pic = components_.pcqa && cop_settings_.pic_weight > 0 && cop_settings_.pic_probes > 0;
  std::vector<torch::Tensor> probe_embeddings;
  if (with_pic) {
    // The probe branch carries no gradient (L_PIC's stop-gradient), so it runs without a graph,
    // and before the original's forward: restoring the running statistics afterwards would
    // touch tensors that forward's graph holds. In training mode the batch norms normalise the
    // probes as a batch of their own; the statistics used at test time stay the real batches'.
    torch::NoGradGuard no_grad;
    const RunningStatisticsGuard keep_statistics(*encoder_);
    for (int n = 0; n < cop_settings_.pic_probes; ++n) {
      probe_embeddings.push_back(encode(features, mix, [&](const torch::Tensor& map) {
        return probe_.intervene(probed(map), context.generator, n);
      }));
    }
  }
  const torch::Tensor original = encode(features, mix, probed);
  if (!components_.pcqa) return {original, {}};
  const torch::Tensor reflections = adapter_->reflections_of(original);
  const auto projection = adapter_->project(reflections, original);
  TrainingEmbedding result{projection.quotient, {}};
  if (with_pic) {
    const PicSpace space = cop_settings_.pic_space;
    std::vector<torch::Tensor> probe_invariants;
    {
      torch::NoGradGuard no_grad;
      for (const auto& probe : probe_embeddings) {
        probe_invariants.push_back(pic_invariant(adapter_->project(reflections.detach(), probe).invariant, probe, space));
      }
    }
    const torch::Tensor invariant = pic_invariant(projection.invariant, original, space);
    result.side_loss = cop_settings_.pic_weight * probe_invariance_loss(invariant, torch::stack(probe_invariants));
  }
  return result;
}

namespace {

// A random `share` of `rows` (rounded), in random order.
std::vector<std::int64_t> random_share(std::vector<std::int64_t> rows, double share, std::mt19937_64& generator) {
  shuffle_with(rows, generator);
  rows.resize(static_cast<std::size_t>(std::lround(share * static_cast<double>(rows.size()))));
  return rows;
}

// Rows of `count` samples in blocks of `per_class`: the first `shots` of each block are support
// samples, the rest queries; each part contributes its own random share.
std::vector<std::int64_t> support_and_query_share(std::int64_t count, std::int64_t per_class, std::int64_t shots,
                                                  double support_share, double query_share,
                                                  std::mt19937_64& generator) {
  std::vector<std::int64_t> support, query;
  for (std::int64_t i = 0; i < count; ++i) (i % per_class < shots ? support : query).push_back(i);
  std::vector<std::int64_t> chosen = random_share(support, support_share, generator);
  const std::vector<std::int64_t> chosen_queries = random_share(query, query_share, generator);
  chosen.insert(chosen.end(), chosen_queries.begin(), chosen_queries.end());
  return chosen;
}

torch::Tensor rows_tensor(const std::vector<std::int64_t>& rows) {
  return rows.empty() ? torch::Tensor() : torch::tensor(rows, torch::kLong);
}

}  // namespace

torch::Tensor CopFscilMethod::pretraining_probe_rows(std::int64_t batch, RunContext& context) {
  if (cop_settings_.pretrain_coverage == 0) return {};
  std::vector<std::int64_t> rows(static_cast<std::size_t>(batch));
  std::iota(rows.begin(), rows.end(), 0);
  return rows_tensor(random_share(rows, cop_settings_.pretrain_coverage, context.generator));
}

void CopFscilMethod::perturb_episode(PitEpisode& episode, RunContext& context) {
  const auto pairs = static_cast<std::int64_t>(episode.first_class.size());
  const std::int64_t per_class = episode.mixed_features.size(0) / pairs;
  const std::int64_t shots = per_class - episode.query_labels.size(0) / pairs;
  episode.mixed_probe_rows = rows_tensor(support_and_query_share(
      episode.mixed_features.size(0), per_class, shots, cop_settings_.support_coverage, cop_settings_.query_coverage,
      context.generator));
  const std::int64_t kept = episode.kept_features.size(0);
  switch (cop_settings_.kept) {
    case KeptCoverage::query:
      episode.kept_probe_rows = rows_tensor(
          support_and_query_share(kept, per_class, 0, 0.0, cop_settings_.query_coverage, context.generator));
      break;
    case KeptCoverage::split:
      episode.kept_probe_rows = rows_tensor(support_and_query_share(
          kept, per_class, shots, cop_settings_.support_coverage, cop_settings_.query_coverage, context.generator));
      break;
    case KeptCoverage::clean:
      break;
  }
}

bool CopFscilMethod::episodes_keep_running_statistics() const {
  return cop_settings_.episode_statistics == EpisodeStatistics::guarded;
}

void CopFscilMethod::after_pseudo_incremental(const SessionData& base, RunContext& context) {
  if (cop_settings_.episode_statistics != EpisodeStatistics::reestimate || settings().pit.epochs == 0) return;
  report_validation(context, "pseudo_incremental_before_reestimation");
  reestimate_batch_norm_statistics(*encoder_, base.features, 256,
                                   [&](const torch::Tensor& batch) { encoder_->forward(batch); });
}

namespace {

// Whether its pretraining is PITS-SC's to the bit, bank included: CPI acts in episodes only, on
// the standardised maps, with the bank pits-sc records, and no adapter trains with the encoder.
bool pretrains_as_pits_sc(const CopFscilSettings& settings, const CopFscilComponents& components) {
  return !components.pcqa && settings.pretrain_coverage == 0 && settings.cpi.space == ProbeSpace::standardised &&
         settings.cpi.bank_capacity == kContextBankCapacity;
}

}  // namespace

bool CopFscilMethod::pretraining_shareable(const RunContext& context) const {
  return PitsScMethod::pretraining_shareable(context) && pretrains_as_pits_sc(cop_settings_, components_);
}

torch::Tensor CopFscilMethod::embed(const torch::Tensor& features) {
  const torch::Tensor embeddings = embed_in_batches(encoder_, features);
  if (!components_.pcqa) return embeddings;
  torch::NoGradGuard no_grad;
  constexpr std::int64_t chunk = 1024;  // bounds the N x m x D reflections
  std::vector<torch::Tensor> parts;
  for (std::int64_t first = 0; first < embeddings.size(0); first += chunk) {
    parts.push_back(adapter_->forward(embeddings.narrow(0, first, std::min(chunk, embeddings.size(0) - first))));
  }
  return torch::cat(parts);
}

int CopFscilMethod::probes_per_support_sample(const InputShape& input) const {
  if (cop_settings_.pspc_probes > 0) return cop_settings_.pspc_probes;
  return default_pspc_probes(input.channels * input.mel_bins * input.frames);
}

torch::Tensor CopFscilMethod::view_probe_embeddings(const torch::Tensor& features, int probes,
                                                    std::mt19937_64& generator) {
  const std::int64_t n = features.size(0);
  const std::int64_t per_chunk = std::max<std::int64_t>(1, 256 / n);  // forwards of about 256 samples
  const InputNormHook view = [&](const torch::Tensor& map) { return probe_.view(map, generator); };
  std::vector<torch::Tensor> parts;
  for (std::int64_t first = 0; first < probes; first += per_chunk) {
    const std::int64_t copies = std::min<std::int64_t>(probes - first, per_chunk);
    const torch::Tensor repeated = features.repeat({copies, 1, 1, 1});
    parts.push_back(encode_for_inference(repeated, view).view({copies, n, -1}));
  }
  return torch::cat(parts);
}

std::pair<torch::Tensor, torch::Tensor> CopFscilMethod::pspc_embeddings(const torch::Tensor& original,
                                                                        const torch::Tensor& probes) {
  if (!components_.pcqa) return {original, probes};
  torch::NoGradGuard no_grad;
  const std::int64_t count = probes.size(0), n = probes.size(1);
  const torch::Tensor flat = probes.reshape({count * n, -1});
  if (!cop_settings_.pspc_q_from_original) return {adapter_->forward(original), adapter_->forward(flat).view(probes.sizes())};
  // Q_i from z_i^(0) for every probe of sample i, as PCQA maps probes (and as L_PIC does).
  const torch::Tensor reflections = adapter_->reflections_of(original);
  const torch::Tensor repeated = reflections.repeat({count, 1, 1});
  return {adapter_->project(reflections, original).quotient,
          adapter_->project(repeated, flat).quotient.view(probes.sizes())};
}

void CopFscilMethod::train_base(const SessionData& base, RunContext& context) {
  PitsScMethod::train_base(base, context);
  if (components_.pcqa && context.validation != nullptr) {
    context.diagnostics["pcqa_dropped_off_fixed_channels"] =
        adapter_->dropped_share_off_fixed_channels(embed_in_batches(encoder_, context.validation->features));
  }
  auto state = std::make_shared<BaseState>();
  state->classifier = ParameterSnapshot(*classifier_);
  state->stored_means = stored_means_.clone();
  state->seen_classes = seen_classes_;
  state->generator = context.generator;
  state->torch_generator_state = torch_random_state();
  base_state_ = std::move(state);
}

bool CopFscilMethod::continue_from_base(Method& trained, RunContext& context) {
  auto* source = dynamic_cast<CopFscilMethod*>(&trained);
  if (source == nullptr || source->base_state_ == nullptr || source->components_.pcqa != components_.pcqa) return false;
  encoder_ = source->encoder_;
  classifier_ = source->classifier_;
  adapter_ = source->adapter_;
  probe_ = source->probe_;
  base_state_ = source->base_state_;
  base_state_->classifier.restore_into(*classifier_);
  stored_means_ = base_state_->stored_means.clone();
  seen_classes_ = base_state_->seen_classes;
  context.generator = base_state_->generator;
  restore_torch_random_state(base_state_->torch_generator_state);
  return true;
}

// Sessions after the base read the adapter besides PITS-SC's state; the probe bank and the
// shared-base snapshot serve base training only.
MethodState CopFscilMethod::save_state() const {
  MethodState state = PitsScMethod::save_state();
  if (components_.pcqa) put_module(state, "adapter.", *adapter_);
  return state;
}

void CopFscilMethod::restore_state(const MethodState& state, RunContext& context) {
  PitsScMethod::restore_state(state, context);  // builds the adapter too
  if (components_.pcqa) take_module(state, "adapter.", *adapter_);
}

ModelCost CopFscilMethod::inference_cost(const InputShape& input) const {
  ModelCost cost = PitsScMethod::inference_cost(input);
  if (components_.pcqa) adapter_->count_cost(cost, "adapter");
  cost.freeze("adapter");  // as in PITS-SC, sessions fine-tune the classifier only
  return cost;
}

void CopFscilMethod::learn_session(const SessionData& support, RunContext& context) {
  if (!components_.pspc && !cop_settings_.session_new_and_old) {
    PitsScMethod::learn_session(support, context);  // session_loss=joint: PITS-SC's update
    return;
  }
  check_session_order(support);
  const torch::Tensor shots = support.features.all();
  const torch::Tensor encoded = encode_for_inference(shots, {});  // z, before PCQA
  torch::Tensor original, new_means;
  if (components_.pspc) {
    const torch::Tensor encoded_probes =
        view_probe_embeddings(shots, probes_per_support_sample(context.input), context.generator);
    torch::Tensor probes;
    std::tie(original, probes) = pspc_embeddings(encoded, encoded_probes);
    const torch::Tensor weights =
        stability_weights(probe_instability(original, probes, cop_settings_.pspc_instability_normalised),
                          support.labels, cop_settings_.pspc_beta);
    context.diagnostics["pspc_effective_shots"] = effective_shots(weights, support.labels);
    new_means = calibrated_prototypes(original, probes, weights, support.labels, support.new_classes,
                                      cop_settings_.pspc_mean_of_views);
  } else {
    torch::NoGradGuard no_grad;  // the adapter is frozen after the base session
    original = components_.pcqa ? adapter_->forward(encoded) : encoded;
    new_means = class_means(original, support.labels, support.new_classes);
  }
  if (components_.pcqa) context.diagnostics["support_encoder_norm"] = encoded.norm(2, 1).mean().item<double>();
  const std::int64_t old_classes = seen_classes_;
  classifier_->set_mu_rows(old_classes, new_means);
  seen_classes_ += static_cast<std::int64_t>(support.new_classes.size());
  if (cop_settings_.session_new_and_old) {
    const torch::Tensor old_means = stored_means_;
    finetune_classifier_rows(classifier_, {settings().epochs_new, settings().lr_new, 0.0}, [&] {
      return new_and_old_loss(classifier_, original, support.labels, old_means, old_classes, seen_classes_);
    });
  } else {
    finetune_session_rows(classifier_, original, support.labels, stored_means_, seen_classes_,
                          {settings().epochs_new, settings().lr_new, settings().lamda_proto});
  }
  stored_means_ = torch::cat({stored_means_, new_means});
  record_session_geometry(context, old_classes, original);
}

std::vector<MethodEntry> cop_fscil_entries() {
  const auto variant = [](const std::string& name, const std::string& summary, CopFscilComponents components) {
    MethodEntry entry = pits_sc_entry();  // its stages, profiles and hints
    entry.name = name;
    entry.summary = summary;
    entry.create = [components](const ParameterSet& params) {
      return std::make_unique<CopFscilMethod>(params, components);
    };
    entry.work = [components](const ParameterSet& read, const RunSizes& sizes) {
      const CopFscilSettings cop = CopFscilSettings::from(read);
      std::vector<StageWork> stages = pits_sc_work(
          read, sizes, pretrains_as_pits_sc(cop, components) ? PitsScMethod::kPretrainingStage : "pretraining");
      if (components.pcqa && cop.pic_weight > 0) {  // L_PIC embeds N_cp probed copies of every training batch
        for (StageWork& stage : stages) {
          if (stage.trained > 0) stage.inferred += cop.pic_probes * stage.trained;
        }
      }
      if (components.pspc) {  // N_ps probe views of every shot
        const int probes = cop.pspc_probes > 0 ? cop.pspc_probes : default_pspc_probes(sizes.sample_values);
        for (StageWork& stage : stages) {
          if (!stage.base) stage.inferred *= 1 + probes;  // the sessions' shots
        }
      }
      return stages;
    };
    entry.session_only_parameters.insert(
        {"session_loss", "pspc_probes", "pspc_beta", "pspc_q", "pspc_instability", "pspc_mean"});
    // Its own values never shape PITS-SC's pretraining; where one would (CPI in pretraining, the
    // bank, PCQA), pretraining_shareable() says so and the run trains its own.
    entry.shared_stages[PitsScMethod::kPretrainingStage].merge(cop_fscil_parameter_names());
    // PSPC acts in sessions only: the variants with and without it share their base.
    entry.shared_base_key = components.pcqa ? "cop-fscil:pcqa" : "cop-fscil:no-pcqa";
    // Smoke embeds 10 probes per shot, not the paper's 100: it checks the machinery, and the 100
    // probes' embeddings were a quarter of the reference protocol's time (ours).
    if (components.pspc) entry.profile_defaults["smoke"].push_back({"pspc_probes", "10"});
    return entry;
  };
  return {variant("cop-fscil/cpi", "CoP-FSCIL ablation: pits-sc with context-probing intervention in "
                  "pseudo-incremental episodes and the paper's L_New + L_Old sessions", {false, false}),
          variant("cop-fscil/cpi+pspc", "CoP-FSCIL ablation: CPI plus probe-stability prototype calibration in "
                  "sessions", {false, true}),
          variant("cop-fscil/cpi+pcqa", "CoP-FSCIL ablation: CPI plus the probe-conditioned quotient adapter with "
                  "L_PIC", {true, false}),
          variant("cop-fscil", "CoP-FSCIL: CPI, PCQA with L_PIC, and PSPC on the pits-sc stages", {true, true})};
}

std::unique_ptr<Method> make_cop_fscil(const ParameterSet& params) {
  return std::make_unique<CopFscilMethod>(params, CopFscilComponents{true, true});
}

}  // namespace fscil
