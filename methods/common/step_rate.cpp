#include "methods/common/step_rate.h"

#include <torch/torch.h>

#include <algorithm>
#include <functional>
#include <vector>

#include "core/stopwatch.h"
#include "methods/common/cosine_classifier.h"
#include "methods/common/encoder_step.h"
#include "methods/common/torch_random_state.h"

namespace fscil {

namespace {

// The median seconds of a step, after one untimed warm-up step (first-touch page faults, oneDNN's
// kernel generation), over at least seven steps and `seconds`: the median, because a few steps
// slowed by other work or by the host would pull a mean (means of one second ranged 2.1-4.3 ms a
// sample on an idle machine, medians 2.05-2.22 in the same half hour).
double seconds_per_step(const std::function<void()>& step, double seconds) {
  constexpr std::size_t kLeastSteps = 7;
  step();
  Stopwatch clock;
  std::vector<double> steps;
  while (steps.size() < kLeastSteps || clock.seconds() < seconds) {
    Stopwatch one;
    step();
    steps.push_back(one.seconds());
  }
  std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
  return steps[steps.size() / 2];
}

double head_step_seconds(std::int64_t embedding_size, double seconds) {
  constexpr std::int64_t kHeadClasses = 100, kHeadBatch = 256;
  torch::nn::Linear layer(embedding_size, embedding_size);
  CosineClassifier classifier(kHeadClasses, embedding_size, 16.0);
  std::vector<torch::Tensor> parameters = layer->parameters();
  parameters.push_back(classifier->weight());
  torch::optim::SGD optimizer(parameters, torch::optim::SGDOptions(0.1).momentum(0.9));
  const torch::Tensor embeddings = torch::randn({kHeadBatch, embedding_size});
  const torch::Tensor labels = torch::randint(kHeadClasses, {kHeadBatch});
  return seconds_per_step([&] {
    optimizer.zero_grad();
    torch::cross_entropy_loss(classifier->forward(layer->forward(embeddings), kHeadClasses), labels).backward();
    optimizer.step();
  }, seconds);
}

// Puts torch's generator back as it was, however the timing ends.
class RandomStateGuard {
 public:
  RandomStateGuard() : state_(torch_random_state()) {}
  ~RandomStateGuard() { restore_torch_random_state(state_); }
  RandomStateGuard(const RandomStateGuard&) = delete;
  RandomStateGuard& operator=(const RandomStateGuard&) = delete;

 private:
  torch::Tensor state_;
};

}  // namespace

StepRate measure_step_rate(std::int64_t channels, std::int64_t mel_bins, std::int64_t frames, std::int64_t batch,
                           double seconds, Precision precision) {
  const RandomStateGuard keep_random_state;
  EncoderStep work(channels, mel_bins, frames, batch, precision);
  StepRate rate;
  rate.train_seconds_per_sample = seconds_per_step([&] { work.train(); }, seconds) / static_cast<double>(batch);
  rate.head_step_seconds = head_step_seconds(work.encoder()->embedding_size(), seconds / 4);
  rate.infer_seconds_per_sample = seconds_per_step([&] { work.infer(); }, seconds / 2) / static_cast<double>(batch);
  return rate;
}

}  // namespace fscil
