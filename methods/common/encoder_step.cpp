#include "methods/common/encoder_step.h"

#include <vector>

#include "methods/common/supervised_training.h"

namespace fscil {

namespace {

std::vector<torch::Tensor> trained_parameters(ResNet18Encoder& encoder, CosineClassifier& classifier) {
  std::vector<torch::Tensor> parameters = encoder->parameters();
  parameters.push_back(classifier->weight());
  return parameters;
}

ResNet18Options encoder_step_options(std::int64_t channels, std::int64_t mel_bins, Precision precision) {
  ResNet18Options options{channels, mel_bins};
  options.precision = precision;
  return options;
}

}  // namespace

EncoderStep::EncoderStep(std::int64_t channels, std::int64_t mel_bins, std::int64_t frames, std::int64_t batch,
                         Precision precision, std::int64_t classes)
    : classes_(classes),
      encoder_(encoder_step_options(channels, mel_bins, precision)),
      classifier_(classes, encoder_->embedding_size(), 16.0),
      optimizer_(make_schedule_sgd(trained_parameters(encoder_, classifier_), SupervisedSchedule{})),
      features_(torch::randn({batch, channels, mel_bins, frames})),
      labels_(torch::randint(classes, {batch})) {}

void EncoderStep::train() {
  encoder_->train();
  optimizer_.zero_grad();
  torch::cross_entropy_loss(classifier_->forward(encoder_->forward(features_), classes_), labels_).backward();
  optimizer_.step();
}

void EncoderStep::infer() {
  encoder_->eval();
  const torch::NoGradGuard no_grad;
  encoder_->forward(features_);
}

}  // namespace fscil
