#pragma once
#include <torch/torch.h>

#include <cstdint>
#include <utility>
#include <vector>

namespace fscil {

// How many features DSN draws per class at each redraw (exemplar.py L54-L83 at 6b6a9bc8): every
// class of the current session gets `current`; an older class min(cap, `regular` + the extra draws
// its confusion earned), the cap being `base_cap` for base classes and `old_cap` for earlier novel
// ones (the release names the caps *_min). The release keeps regular + extra as one count p, set
// back to sample_k (`regular`) after each draw; keeping the extra alone leaves sample_k out of the
// base session's state.
struct DrawCounts {
  int current = 4, base_cap = 4, old_cap = 4, regular = 4;
};

// Features drawn from the class Gaussians, labelled with their classes. The release labels the
// current session's draws with minus the class (ex L77-L78) to route them with the real shots;
// the labels themselves tell which they are.
struct GaussianDraws {
  torch::Tensor features, labels;
};

// DSN's memory of every seen class (exemplar.py, "Exemplar"): a mean and a full covariance of its
// embeddings, and the extra draws it has earned. It is the only thing DSN keeps of old classes: no sample is stored.
// The covariances are kept in float32 (the release keeps numpy float64: ours, to halve the state).
class ClassGaussiansImpl : public torch::nn::Module {
 public:
  ClassGaussiansImpl(std::int64_t classes, std::int64_t embedding_size);
  // Classes [first, first + means.size(0)) seen for the first time: stored as given (ex L41-L43).
  void insert(std::int64_t first, const torch::Tensor& means, const torch::Tensor& covariances);
  // The release's update of known classes (ex L37-L46): mean and covariance <- 0.8 old + 0.2 new.
  void blend(std::int64_t first, const torch::Tensor& means, const torch::Tensor& covariances);
  // Draws for every class in [0, seen) in class order from torch's global generator, the session's
  // classes being [current_first, seen); each class's extra draws are then spent (ex L82).
  GaussianDraws draw(std::int64_t seen, std::int64_t base_classes, std::int64_t current_first, const DrawCounts& counts);
  // One more draw for an old class the current session's shots are confused with (ex L190-L197).
  void add_draw(std::int64_t cls) { extra_draws_[cls] += 1; }

  const torch::Tensor& means() const { return means_; }
  const torch::Tensor& covariances() const { return covariances_; }
  const torch::Tensor& extra_draws() const { return extra_draws_; }

 private:
  torch::Tensor means_, covariances_, extra_draws_;
  // Each class's sampling factor, kept while its covariance does not change (old classes' never do).
  // Not state: a restored method is built afresh, with an empty cache.
  std::vector<torch::Tensor> factors_;
};
TORCH_MODULE(ClassGaussians);

}  // namespace fscil
