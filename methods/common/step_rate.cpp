#include "methods/common/step_rate.h"

#include <torch/torch.h>

#include <functional>

#include "core/stopwatch.h"
#include "methods/common/cosine_classifier.h"
#include "methods/common/resnet18.h"
#include "methods/common/supervised_training.h"
#include "methods/common/torch_random_state.h"

namespace fscil {

namespace {

// Seconds per step after one untimed warm-up step (first-touch page faults, oneDNN's kernel
// generation), over at least two steps and `seconds`.
double seconds_per_step(const std::function<void()>& step, double seconds) {
  step();
  Stopwatch clock;
  int steps = 0;
  while (steps < 2 || clock.seconds() < seconds) {
    step();
    ++steps;
  }
  return clock.seconds() / steps;
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
                           double seconds) {
  constexpr std::int64_t kClasses = 60;
  const RandomStateGuard keep_random_state;
  ResNet18Encoder encoder(ResNet18Options{channels, mel_bins});
  CosineClassifier classifier(kClasses, encoder->embedding_size(), 16.0);
  std::vector<torch::Tensor> parameters = encoder->parameters();
  parameters.push_back(classifier->weight());
  auto optimizer = make_nesterov_sgd(parameters, SupervisedSchedule{});
  const torch::Tensor features = torch::randn({batch, channels, mel_bins, frames});
  const torch::Tensor labels = torch::randint(kClasses, {batch});

  StepRate rate;
  encoder->train();
  rate.train_seconds_per_sample = seconds_per_step([&] {
    optimizer.zero_grad();
    torch::cross_entropy_loss(classifier->forward(encoder->forward(features), kClasses), labels).backward();
    optimizer.step();
  }, seconds) / static_cast<double>(batch);
  rate.head_step_seconds = head_step_seconds(encoder->embedding_size(), seconds / 4);
  encoder->eval();
  torch::NoGradGuard no_grad;
  rate.infer_seconds_per_sample =
      seconds_per_step([&] { encoder->forward(features); }, seconds / 2) / static_cast<double>(batch);
  return rate;
}

}  // namespace fscil
