#include "methods/dsn/gaussian_replay.h"

#include <cmath>
#include <vector>

namespace fscil {

GaussianReplay::GaussianReplay(ClassGaussiansImpl& gaussians, const torch::Tensor& shots, const torch::Tensor& shot_labels,
                               std::int64_t first, std::int64_t base_classes, const torch::Tensor& shot_means,
                               const torch::Tensor& shot_covariances, const DrawCounts& counts, int refresh_every)
    : gaussians_(gaussians),
      shots_(shots),
      shot_labels_(shot_labels),
      shot_means_(shot_means),
      shot_covariances_(shot_covariances),
      first_(first),
      base_classes_(base_classes),
      counts_(counts),
      refresh_every_(refresh_every) {}

void GaussianReplay::start_epoch(int epoch) {
  if (epoch % refresh_every_ != 0) return;
  working_means_ = shot_means_.clone();
  working_covariances_ = shot_covariances_.clone();
  gaussians_.blend(first_, working_means_, working_covariances_);  // L279 -> L204
  const GaussianDraws draws = gaussians_.draw(first_ + shot_means_.size(0), base_classes_, first_, counts_);  // L280-L286
  features_ = torch::cat({draws.features, shots_});
  labels_ = torch::cat({draws.labels, shot_labels_});
  is_real_shot_ = torch::cat({torch::zeros({draws.labels.size(0)}, torch::kBool), torch::ones({shots_.size(0)}, torch::kBool)});
}

void GaussianReplay::end_epoch(int epoch, const ShotConfusion& confusion) {
  torch::NoGradGuard no_grad;
  const torch::Tensor base_covariances = gaussians_.covariances().slice(0, 0, base_classes_);
  std::vector<torch::Tensor> calibrated;
  for (std::int64_t c = 0; c < shot_means_.size(0); ++c) {
    calibrated.push_back(calibrated_covariance(working_covariances_[c], confusion.base_weights(c), base_covariances));
  }
  working_covariances_.copy_(torch::stack(calibrated));
  gaussians_.blend(first_, working_means_, working_covariances_);
  if (kept_epoch_ >= 0 && kept_epoch_ / refresh_every_ == epoch / refresh_every_) {
    kept_covariances_ = working_covariances_.clone();
  }
}

void GaussianReplay::keep(int epoch) {
  kept_epoch_ = epoch;
  kept_means_ = working_means_.clone();
  kept_covariances_ = working_covariances_.clone();
}

void GaussianReplay::finish() {
  if (kept_epoch_ < 0) {
    kept_means_ = working_means_;
    kept_covariances_ = working_covariances_;
  }
  if (kept_means_.defined()) gaussians_.blend(first_, kept_means_, kept_covariances_);
}

double gaussian_replay_head_steps(const RunSizes& sizes, int epochs, int batch, double steps_per_class,
                                  const std::function<double(int session)>& samples) {
  double steps = 0;
  for (int session = 1; session < sizes.sessions; ++session) {
    steps += epochs * (std::ceil(samples(session) / batch) + steps_per_class * sizes.classes_before(session));
  }
  return steps;
}

}  // namespace fscil
