#pragma once
#include <memory>

#include "methods/cop_fscil/context_probe.h"
#include "methods/cop_fscil/cop_fscil_settings.h"
#include "methods/cop_fscil/quotient_adapter.h"
#include "methods/common/parameter_snapshot.h"
#include "methods/pits_sc/pits_sc_method.h"

namespace fscil {

// CoP-FSCIL (the seed paper) on the PITS-SC stages:
// - CPI perturbs a share of each pseudo-incremental episode's support and query samples, on the
//   map after bn0 (cpi_space=standardised) or on the dB input (raw);
// - PCQA (optional) sits after the encoder, trained with L_CE + lambda L_PIC in both base
//   stages, and every classification uses its output z_hat;
// - PSPC (optional) builds each new prototype from probe-stability weights; without it a new
//   prototype is the mean support embedding;
// - every session fine-tunes the rows with L_New over the new classes plus L_Old over the old
//   ones (session_loss=new-old; joint is PITS-SC's update).
// Without PCQA the embedding is the encoder's.
class CopFscilMethod : public PitsScMethod {
 public:
  CopFscilMethod(const ParameterSet& params, CopFscilComponents components);
  void train_base(const SessionData& base, RunContext& context) override;
  void learn_session(const SessionData& support, RunContext& context) override;
  bool continue_from_base(Method& trained, RunContext& context) override;
  torch::Tensor embed(const torch::Tensor& features) override;
  ModelCost inference_cost(const InputShape& input) const override;
  MethodState save_state() const override;
  void restore_state(const MethodState& state, RunContext& context) override;

  // For tests.
  const CopFscilComponents& components() const { return components_; }
  QuotientAdapter& adapter() { return adapter_; }  // empty without PCQA
  int probes_per_support_sample(const InputShape& input) const;

 protected:
  void build_network(RunContext& context) override;
  std::vector<torch::Tensor> network_parameters() override;
  std::vector<torch::nn::Module*> extra_trained_modules() override;
  TrainingEmbedding training_embedding(const torch::Tensor& features, const InputNormHook& mix,
                                       const torch::Tensor& probe_rows, RunContext& context) override;
  torch::Tensor pretraining_probe_rows(std::int64_t batch, RunContext& context) override;
  void perturb_episode(PitEpisode& episode, RunContext& context) override;
  bool episodes_keep_running_statistics() const override;
  void after_pseudo_incremental(const SessionData& base, RunContext& context) override;
  // PITS-SC's pretraining is CPI's when CPI does not act in it and no adapter trains with it.
  bool pretraining_shareable(const RunContext& context) const override;
  ContextStatisticBank& context_bank() override { return probe_.bank(); }
  // PSPC's z_hat of the originals' encoder embeddings (N x D) and of their probes' (N_ps x N x D).
  std::pair<torch::Tensor, torch::Tensor> pspc_embeddings(const torch::Tensor& original, const torch::Tensor& probes);

 private:
  // The encoder's embedding in training mode with `mix` applied after bn0 and `probe` where CPI
  // acts: to the input (cpi_space=raw) or to the map after bn0 and `mix` (standardised). Empty
  // hooks change nothing.
  torch::Tensor encode(const torch::Tensor& features, const InputNormHook& mix, const InputNormHook& probe);
  // The same in eval mode, without gradients, in batches.
  torch::Tensor encode_for_inference(const torch::Tensor& features, const InputNormHook& probe);
  // PSPC: the encoder's embeddings of N_ps random-view probes of every support sample: N_ps x N x D.
  torch::Tensor view_probe_embeddings(const torch::Tensor& features, int probes, std::mt19937_64& generator);

  CopFscilSettings cop_settings_;
  CopFscilComponents components_;
  ContextProbe probe_;
  QuotientAdapter adapter_{nullptr};
  // What sessions change, as train_base left it: the classifier, the stored means and the
  // random state (the encoder, bn0, adapter and probe bank are frozen after the base session).
  struct BaseState {
    ParameterSnapshot classifier;
    torch::Tensor stored_means;
    std::int64_t seen_classes = 0;
    std::mt19937_64 generator;
    torch::Tensor torch_generator_state;
  };
  std::shared_ptr<const BaseState> base_state_;
};

// cop-fscil/cpi, cop-fscil/cpi+pspc, cop-fscil/cpi+pcqa and cop-fscil, in the ablation's order.
std::vector<MethodEntry> cop_fscil_entries();
std::unique_ptr<Method> make_cop_fscil(const ParameterSet& params);

}  // namespace fscil
