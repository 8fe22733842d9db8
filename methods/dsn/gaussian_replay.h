#pragma once
#include <torch/torch.h>

#include <cstdint>
#include <functional>

#include "methods/dsn/class_gaussians.h"
#include "methods/dsn/shot_confusion.h"
#include "methods/method_registry.h"

namespace fscil {

// A session's training set as DSN builds it (Inc_train.py L277-L398 at 5bc87b96; AMFO's
// Inc_train.py keeps it, L356-L379 and L462-L465 at 26b2d3f2): every `refresh_every` epochs the session's statistics are re-estimated from its shots
// (without augmentation, ours, so the same each time), blended into the Gaussians and every seen
// class drawn again, the real shots beside the draws; after each epoch the session's covariances
// are calibrated toward the base ones by the shots' confusion and blended again.
//
// `working`: the release's memory_mean / memory_cov, calibrated after each epoch on top of the last
// calibration. `kept`: best_mean / best_cov, what the Gaussians end with. The release keeps a
// reference to the dict, so the calibrations after the kept epoch reach best_cov until the next
// re-estimation makes a new dict (L279, L354, L386).
class GaussianReplay {
 public:
  GaussianReplay(ClassGaussiansImpl& gaussians, const torch::Tensor& shots, const torch::Tensor& shot_labels,
                 std::int64_t first, std::int64_t base_classes, const torch::Tensor& shot_means,
                 const torch::Tensor& shot_covariances, const DrawCounts& counts, int refresh_every);
  // Re-estimates and redraws at the epochs that do (L279-L286).
  void start_epoch(int epoch);
  // Calibrates and blends the session's statistics after `epoch` (L352-L355).
  void end_epoch(int epoch, const ShotConfusion& confusion);
  // `epoch` was chosen: its statistics are the ones the Gaussians keep.
  void keep(int epoch);
  // Blends the kept statistics, or the last ones when no epoch was chosen (L398).
  void finish();

  const torch::Tensor& features() const { return features_; }
  const torch::Tensor& labels() const { return labels_; }
  const torch::Tensor& is_real_shot() const { return is_real_shot_; }

 private:
  ClassGaussiansImpl& gaussians_;
  torch::Tensor shots_, shot_labels_, shot_means_, shot_covariances_;
  std::int64_t first_, base_classes_;
  DrawCounts counts_;
  int refresh_every_;
  int kept_epoch_ = -1;
  torch::Tensor working_means_, working_covariances_, kept_means_, kept_covariances_;
  torch::Tensor features_, labels_, is_real_shot_;
};

// The head steps of sessions built so (MethodEntry::work of dsn and amfo): `epochs` passes over each
// session's shots and draws, `samples(s)` of them in session s, in batches of `batch`, and per epoch
// `steps_per_class` for every class seen before the session: the small operations each class's
// draws, calibration and loss terms take, which no batch count shows (measured: docs/profiling.md).
double gaussian_replay_head_steps(const RunSizes& sizes, int epochs, int batch, double steps_per_class,
                                  const std::function<double(int session)>& samples);

}  // namespace fscil
