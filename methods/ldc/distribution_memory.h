#pragma once
#include <torch/torch.h>

#include <cstdint>
#include <vector>

namespace fscil {

// What LDC keeps of every class instead of samples (the paper's "memory-free" distributions): one
// covariance shared by all classes (mean_cov) and, per class, the few features drawn for it from
// N(its mean, that covariance) when it arrived, which every later session calibrates and replays
// (g_samples, Network.py L191-L192 and L214-L217 at 4548445c). A base class keeps the first of the
// features drawn to train the PCU (L216). Classes a class-variable protocol removes are marked and
// replayed no more (ours: the release has no removal).
class DistributionMemoryImpl : public torch::nn::Module {
 public:
  DistributionMemoryImpl(std::int64_t classes, std::int64_t kept_per_class, std::int64_t dim);

  // The base classes' covariances, averaged (replace_base_fc, helper.py L45).
  void start_covariance(const torch::Tensor& base_covariances);
  // A session's classes one after another, as update_fc_avg folds them (Network.py L189-L190):
  // covariance <- (covariance * base_classes + class covariance * n) / (base_classes + n), n the
  // session's class count.
  void fold_covariances(const torch::Tensor& session_covariances, std::int64_t base_classes);
  // `count` features per class from N(mean, shared covariance), classes x count x D, drawn in class
  // order from torch's global generator.
  torch::Tensor draw(const torch::Tensor& means, std::int64_t count) const;
  // Keeps the first kept_per_class of each class's draws for classes [first, first + draws.size(0)).
  void keep(std::int64_t first, const torch::Tensor& draws);
  void forget(const std::vector<std::int64_t>& classes);
  // LDC's features: the encoder's embeddings times one scale, fixed after the pretraining so that the
  // base embeddings' root mean square is ldc_unit_rms (ours, docs/methods.md "ldc": the PCU's softmax
  // over a feature's dimensions and the rows' fine-tuning steps assume the release's feature scale).
  void set_unit_scale(double scale) { unit_scale_.fill_(scale); }
  torch::Tensor to_unit(const torch::Tensor& features) const { return features * unit_scale_; }

  // The kept features of classes [0, seen) not removed, in class order, and their labels.
  torch::Tensor kept_features(std::int64_t seen) const;
  torch::Tensor kept_labels(std::int64_t seen) const;
  // Whether each of classes [0, seen) is still present (not removed).
  torch::Tensor present(std::int64_t seen) const { return ~removed_.slice(0, 0, seen); }
  const torch::Tensor& covariance() const { return covariance_; }

 private:
  torch::Tensor covariance_, kept_, removed_, unit_scale_;
};
TORCH_MODULE(DistributionMemory);

}  // namespace fscil
