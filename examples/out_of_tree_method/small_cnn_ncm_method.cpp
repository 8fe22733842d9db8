#include "small_cnn_ncm_method.h"

#include <core/valid_range.h>

#include <algorithm>

namespace F = torch::nn::functional;

// Hyper-parameters come from --set KEY=VALUE; reading them here makes bad values fail before training.
SmallCnnNcmMethod::SmallCnnNcmMethod(const fscil::ParameterSet& params)
    : epochs_(params.integer("ncm_epochs", 3, fscil::ValidRange::at_least(1))),
      learning_rate_(params.real("ncm_learning_rate", 1e-3, fscil::ValidRange::above(0))),
      width_(params.integer("ncm_width", 32, fscil::ValidRange::at_least(1))) {}

fscil::NamedModules SmallCnnNcmMethod::build(const fscil::RunContext& context) {
  encoder_ = torch::nn::Sequential(
      torch::nn::Conv2d(torch::nn::Conv2dOptions(context.input.channels, width_, 3).padding(1).bias(false)),
      torch::nn::BatchNorm2d(width_), torch::nn::ReLU(),
      torch::nn::Conv2d(torch::nn::Conv2dOptions(width_, width_, 3).stride(2).padding(1).bias(false)),
      torch::nn::BatchNorm2d(width_), torch::nn::ReLU(),
      torch::nn::AdaptiveAvgPool2d(torch::nn::AdaptiveAvgPool2dOptions({1, 1})), torch::nn::Flatten());
  means_ = ClassMeans(context.total_classes, width_);
  return {{"encoder", encoder_.ptr()}, {"means", means_.ptr()}};
}

void SmallCnnNcmMethod::train_base(const fscil::SessionData& base, fscil::RunContext& context) {
  build_modules(context);
  torch::nn::Linear base_head(width_, context.base_classes);
  std::vector<torch::Tensor> parameters = encoder_->parameters();
  for (const auto& parameter : base_head->parameters()) parameters.push_back(parameter);
  torch::optim::Adam optimizer(parameters, torch::optim::AdamOptions(learning_rate_));
  const std::int64_t batch = 64, samples = base.labels.size(0);
  encoder_->train();
  for (int epoch = 0; epoch < epochs_; ++epoch) {
    const torch::Tensor order = torch::randperm(samples, torch::kLong);  // torch's generator, seeded by the run
    double loss_sum = 0;
    for (std::int64_t first = 0; first < samples; first += batch) {
      const torch::Tensor index = order.narrow(0, first, std::min(batch, samples - first));
      const torch::Tensor loss = F::cross_entropy(base_head(encoder_->forward(base.features.gather(index))),
                                                  base.labels.index_select(0, index));
      optimizer.zero_grad();
      loss.backward();
      optimizer.step();
      loss_sum += loss.item<double>() * static_cast<double>(index.size(0));
    }
    context.log_epoch("base", epoch + 1, static_cast<int>(epochs_), {{"loss", loss_sum / static_cast<double>(samples)}});
  }
  add_class_means(base);
}

void SmallCnnNcmMethod::learn_session(const fscil::SessionData& support, fscil::RunContext& context) {
  add_class_means(support);
}

void SmallCnnNcmMethod::add_class_means(const fscil::SessionData& data) {
  const torch::Tensor embeddings = F::normalize(embed_rows(data.features), F::NormalizeFuncOptions().dim(1));
  torch::NoGradGuard no_grad;
  for (const std::int64_t label : data.new_classes) {
    means_->rows[label] = embeddings.index({data.labels == label}).mean(0);
  }
  const auto last = *std::max_element(data.new_classes.begin(), data.new_classes.end());
  means_->seen.fill_(std::max(means_->seen.item<std::int64_t>(), last + 1));
}

torch::Tensor SmallCnnNcmMethod::embed(const torch::Tensor& features) {
  torch::NoGradGuard no_grad;
  encoder_->eval();
  return encoder_->forward(features);
}

torch::Tensor SmallCnnNcmMethod::classify(const torch::Tensor& embeddings) {
  torch::NoGradGuard no_grad;
  const torch::Tensor seen_means = means_->rows.narrow(0, 0, means_->seen.item<std::int64_t>());
  return torch::mm(F::normalize(embeddings, F::NormalizeFuncOptions().dim(1)),
                   F::normalize(seen_means, F::NormalizeFuncOptions().dim(1)).t());
}

std::unique_ptr<fscil::Method> make_small_cnn_ncm_method(const fscil::ParameterSet& params) {
  return std::make_unique<SmallCnnNcmMethod>(params);
}
