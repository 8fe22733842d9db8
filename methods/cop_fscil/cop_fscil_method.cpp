#include "methods/cop_fscil/cop_fscil_method.h"

#include <cmath>
#include <numeric>

#include "methods/common/embedding.h"
#include "methods/common/module_state.h"
#include "methods/common/running_statistics_guard.h"
#include "methods/common/torch_random_state.h"
#include "methods/cop_fscil/stability_calibration.h"
#include "methods/pits_sc/session_finetune.h"
#include "protocols/seeded_shuffle.h"

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
  const auto invariant = static_cast<std::int64_t>(std::lround(cop_settings_.invariant_fraction * dim));
  adapter_ = QuotientAdapter(QuotientAdapterOptions{dim, cop_settings_.reflections, std::max<std::int64_t>(1, invariant)});
}

std::vector<torch::Tensor> CopFscilMethod::network_parameters() {
  std::vector<torch::Tensor> parameters = PitsScMethod::network_parameters();
  if (components_.pcqa) {
    for (const auto& parameter : adapter_->parameters()) parameters.push_back(parameter);
  }
  return parameters;
}

TrainingEmbedding CopFscilMethod::training_embedding(const torch::Tensor& features, RunContext& context) {
  if (!components_.pcqa) return PitsScMethod::training_embedding(features, context);
  const bool with_pic = cop_settings_.pic_weight > 0 && cop_settings_.pic_probes > 0;
  std::vector<torch::Tensor> probe_embeddings;
  if (with_pic) {
    // The probe branch carries no gradient (L_PIC's stop-gradient), so it runs without a graph,
    // and before the original's forward: restoring the running statistics afterwards would
    // touch tensors that forward's graph holds. In training mode the batch norms normalise the
    // probes as a batch of their own; the statistics used at test time stay the real batches'.
    torch::NoGradGuard no_grad;
    const RunningStatisticsGuard keep_statistics(*encoder_);
    for (int n = 0; n < cop_settings_.pic_probes; ++n) {
      probe_embeddings.push_back(encoder_->forward(probe_.intervene(features, context.generator)));
    }
  }
  const torch::Tensor original = encoder_->forward(features);
  const torch::Tensor reflections = adapter_->reflections_of(original);
  const auto projection = adapter_->project(reflections, original);
  TrainingEmbedding result{projection.quotient, {}};
  if (with_pic) {
    std::vector<torch::Tensor> probe_invariants;
    {
      torch::NoGradGuard no_grad;
      for (const auto& probe : probe_embeddings) {
        probe_invariants.push_back(adapter_->project(reflections.detach(), probe).invariant);
      }
    }
    result.side_loss =
        cop_settings_.pic_weight * probe_invariance_loss(projection.invariant, torch::stack(probe_invariants));
  }
  if (!bank_fed_by_episodes_) probe_.observe(features);
  return result;
}

void CopFscilMethod::intervene_on_share(torch::Tensor& features, const std::vector<std::int64_t>& rows, double share,
                                        std::mt19937_64& generator) {
  std::vector<std::int64_t> chosen = rows;
  shuffle_with(chosen, generator);
  chosen.resize(static_cast<std::size_t>(std::lround(share * static_cast<double>(rows.size()))));
  if (chosen.empty()) return;
  const torch::Tensor index = torch::tensor(chosen);
  features = features.index_copy(0, index, probe_.intervene(features.index_select(0, index), generator));
}

void CopFscilMethod::perturb_episode(PitEpisode& episode, RunContext& context) {
  bank_fed_by_episodes_ = true;
  probe_.observe(episode.kept_features);
  probe_.observe(episode.mixed_features);
  const auto pairs = static_cast<std::int64_t>(episode.first_class.size());
  const std::int64_t per_class = episode.mixed_features.size(0) / pairs;
  const std::int64_t queries = episode.query_labels.size(0) / pairs;
  const std::int64_t shots = per_class - queries;
  std::vector<std::int64_t> support_rows, query_rows;
  for (std::int64_t j = 0; j < pairs; ++j) {
    for (std::int64_t i = 0; i < per_class; ++i) (i < shots ? support_rows : query_rows).push_back(j * per_class + i);
  }
  std::vector<std::int64_t> kept_rows(static_cast<std::size_t>(episode.kept_features.size(0)));
  std::iota(kept_rows.begin(), kept_rows.end(), 0);
  intervene_on_share(episode.mixed_features, support_rows, cop_settings_.support_coverage, context.generator);
  intervene_on_share(episode.mixed_features, query_rows, cop_settings_.query_coverage, context.generator);
  intervene_on_share(episode.kept_features, kept_rows, cop_settings_.query_coverage, context.generator);
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

torch::Tensor CopFscilMethod::probe_embeddings(const torch::Tensor& features, int probes,
                                               std::mt19937_64& generator) {
  const std::int64_t n = features.size(0);
  const std::int64_t per_chunk = std::max<std::int64_t>(1, 256 / n);  // forwards of about 256 samples
  std::vector<torch::Tensor> parts;
  for (std::int64_t first = 0; first < probes; first += per_chunk) {
    std::vector<torch::Tensor> views;
    for (std::int64_t k = first; k < std::min<std::int64_t>(probes, first + per_chunk); ++k) {
      views.push_back(probe_.view(features, generator));
    }
    parts.push_back(embed(torch::cat(views)).view({static_cast<std::int64_t>(views.size()), n, -1}));
  }
  return torch::cat(parts);
}

void CopFscilMethod::train_base(const SessionData& base, RunContext& context) {
  PitsScMethod::train_base(base, context);
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
  if (source == nullptr || source->base_state_ == nullptr || source->shared_base_key() != shared_base_key()) return false;
  encoder_ = source->encoder_;
  classifier_ = source->classifier_;
  adapter_ = source->adapter_;
  probe_ = source->probe_;
  bank_fed_by_episodes_ = source->bank_fed_by_episodes_;
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
  if (!components_.pspc) {
    PitsScMethod::learn_session(support, context);
    return;
  }
  check_session_order(support);
  const torch::Tensor shots = support.features.all();
  const torch::Tensor original = embed(shots);
  const torch::Tensor probes = probe_embeddings(shots, probes_per_support_sample(context.input), context.generator);
  const torch::Tensor weights =
      stability_weights(probe_instability(original, probes), support.labels, cop_settings_.pspc_beta);
  const torch::Tensor new_means = calibrated_prototypes(original, probes, weights, support.labels, support.new_classes);
  const std::int64_t old_classes = seen_classes_;
  classifier_->set_mu_rows(old_classes, new_means);
  seen_classes_ += static_cast<std::int64_t>(support.new_classes.size());
  const torch::Tensor old_means = stored_means_;
  finetune_classifier_rows(classifier_, {settings().epochs_new, settings().lr_new, 0.0}, [&] {
    return new_and_old_loss(classifier_, original, support.labels, old_means, old_classes, seen_classes_);
  });
  stored_means_ = torch::cat({stored_means_, new_means});
}

std::unique_ptr<Method> make_cop_fscil_cpi(const ParameterSet& params) {
  return std::make_unique<CopFscilMethod>(params, CopFscilComponents{false, false});
}
std::unique_ptr<Method> make_cop_fscil_cpi_pspc(const ParameterSet& params) {
  return std::make_unique<CopFscilMethod>(params, CopFscilComponents{false, true});
}
std::unique_ptr<Method> make_cop_fscil_cpi_pcqa(const ParameterSet& params) {
  return std::make_unique<CopFscilMethod>(params, CopFscilComponents{true, false});
}
std::unique_ptr<Method> make_cop_fscil(const ParameterSet& params) {
  return std::make_unique<CopFscilMethod>(params, CopFscilComponents{true, true});
}

}  // namespace fscil
