#pragma once
#include <functional>
#include <memory>
#include <vector>

#include "methods/common/parameter_snapshot.h"
#include "methods/common/resnet18.h"
#include "methods/method.h"
#include "methods/orco/orco_settings.h"
#include "methods/orco/projector.h"
#include "methods/orco/replay_memory.h"

namespace fscil {

// OrCo-style baseline (CVPR 2024, noorahmedds/OrCo): pseudo-targets spread over the projection
// sphere, classes Hungarian-assigned to them, a projector trained towards them with supervised
// contrastive, orthogonality and cross-entropy losses, and a replay memory of real old samples.
// The encoder is frozen after phase 1; only the projector learns afterwards.
class OrcoMethod : public Method {
 public:
  explicit OrcoMethod(const ParameterSet& params);
  void train_base(const SessionData& base, RunContext& context) override;
  void learn_session(const SessionData& support, RunContext& context) override;
  torch::Tensor embed(const torch::Tensor& features) override;
  torch::Tensor classify(const torch::Tensor& embeddings) override;
  ModelCost inference_cost(const InputShape& input) const override;
  MethodState save_state() const override;
  void restore_state(const MethodState& state, RunContext& context) override;
  ReplayFootprint replay_footprint() const override { return {memory_.samples(), memory_.bytes()}; }

  const ReplayMemory& replay_memory() const { return memory_; }
  Projector& projector() { return projector_; }
  const ParameterSnapshot& phase_two_projector() const { return phase_two_projector_; }
  const torch::Tensor& targets() const { return targets_; }
  // Target row of each seen class, in class order.
  const std::vector<std::int64_t>& class_targets() const { return class_targets_; }

 private:
  // What the projector's loss sees besides the batch: targets of the seen classes, the targets
  // to perturb into the contrastive batch, and which classes the cross-entropy covers.
  struct ProjectorObjective {
    torch::Tensor perturbed_targets, perturbed_labels;
    std::int64_t novel_from_class = 0;  // the cross-entropy weighs classes below it apart
    double base_ce_weight = 1.0, novel_ce_weight = 1.0;
    std::int64_t orthogonality_from_class = 0;  // orthogonality over these classes' samples only
  };

  void pretrain(const SessionData& base, RunContext& context);
  // V masked views of every sample through the frozen encoder: N x V x D.
  torch::Tensor encoded_views(const SampleRows& features, RunContext& context);
  torch::Tensor project(const torch::Tensor& encodings);
  void assign_classes(const SampleRows& features, const torch::Tensor& labels,
                      const std::vector<std::int64_t>& classes);
  std::vector<std::int64_t> free_target_rows() const;
  torch::Tensor seen_targets() const;
  torch::Tensor unassigned_targets() const;
  // `score` (may be empty: keep the last epoch) rates the projector for `session_stop`.
  // With a `score`, the projector of the best-scoring check (every stop.check_every epochs and at
  // the last) is kept, training stops after stop.patience checks without a better one, and the
  // diagnostics `<kept>_kept_epoch`, `<kept>_epochs_trained` and `<kept>_stop_score` say so.
  // `after_epoch` (may be empty) is called after each epoch is logged.
  void train_projector(const torch::Tensor& views, const torch::Tensor& labels, const ProjectorSchedule& schedule,
                       const ProjectorObjective& objective, const std::function<double()>& score,
                       const SessionStop& stop, RunContext& context, const std::string& phase,
                       const std::string& kept, const std::function<void()>& after_epoch = {});
  // Accuracy (%) of frozen-encoder embeddings `encodings` of `data`'s base classes and of the rest
  // against the seen targets, and their harmonic mean (the reference's session score).
  double harmonic_mean_of(const torch::Tensor& encodings, const torch::Tensor& labels);
  // Accuracy (%) of encoder embeddings against the seen classes' targets.
  double accuracy_of(const torch::Tensor& encodings, const torch::Tensor& labels);

  OrcoSettings settings_;
  ResNet18Encoder encoder_{nullptr};
  Projector projector_{nullptr};
  ParameterSnapshot phase_two_projector_;
  torch::Tensor targets_;                     // every class of the protocol gets one row
  std::vector<std::int64_t> class_targets_;   // target row of class c
  std::vector<bool> target_taken_;
  std::int64_t base_classes_ = 0;
  ReplayMemory memory_;
};

MethodEntry orco_entry();

}  // namespace fscil
