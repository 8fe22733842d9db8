#include "methods/common/supervised_training.h"

#include <cmath>

#include "core/stop_request.h"
#include "methods/common/shuffled_batches.h"

namespace fscil {

SupervisedSchedule SupervisedSchedule::from(const ParameterSet& params) {
  SupervisedSchedule schedule;
  schedule.epochs = static_cast<int>(params.integer("pretrain_epochs", schedule.epochs, ValidRange::at_least(0)));
  schedule.learning_rate = params.real("pretrain_lr", schedule.learning_rate, ValidRange::above(0));
  schedule.batch_size = static_cast<int>(params.integer("batch_size", schedule.batch_size, ValidRange::at_least(2)));
  schedule.momentum = params.real("momentum", schedule.momentum, ValidRange::from_up_to(0, 1));
  schedule.weight_decay = params.real("weight_decay", schedule.weight_decay, ValidRange::at_least(0));
  schedule.lr_step = static_cast<int>(params.integer("lr_step", schedule.lr_step, ValidRange::at_least(1)));
  schedule.lr_gamma = params.real("lr_gamma", schedule.lr_gamma, ValidRange::above_up_to(0, 1));
  return schedule;
}

torch::optim::SGD make_nesterov_sgd(const std::vector<torch::Tensor>& parameters, const SupervisedSchedule& schedule) {
  return torch::optim::SGD(parameters, torch::optim::SGDOptions(schedule.learning_rate)
                                           .momentum(schedule.momentum)
                                           .nesterov(true)
                                           .weight_decay(schedule.weight_decay));
}

void set_epoch_learning_rate(torch::optim::SGD& optimizer, const SupervisedSchedule& schedule, int epoch) {
  const double rate = schedule.learning_rate * std::pow(schedule.lr_gamma, epoch / schedule.lr_step);
  for (auto& group : optimizer.param_groups()) static_cast<torch::optim::SGDOptions&>(group.options()).lr(rate);
}

double train_epochs(const std::vector<torch::Tensor>& parameters, const BatchLoss& batch_loss, const SessionData& data,
                    const SupervisedSchedule& schedule, RunContext& context, const std::string& phase,
                    const std::function<void(int)>& after_epoch) {
  return train_epochs_while(parameters, batch_loss, data, schedule, context, phase, [&](int epoch) {
    if (after_epoch) after_epoch(epoch);
    return true;
  });
}

double train_epochs_while(const std::vector<torch::Tensor>& parameters, const BatchLoss& batch_loss,
                          const SessionData& data, const SupervisedSchedule& schedule, RunContext& context,
                          const std::string& phase, const std::function<bool(int)>& keep_going) {
  torch::optim::SGD optimizer = make_nesterov_sgd(parameters, schedule);
  double last_loss = 0;
  for (int epoch = 0; epoch < schedule.epochs; ++epoch) {
    set_epoch_learning_rate(optimizer, schedule, epoch);
    double loss_sum = 0;
    std::int64_t batches = 0;
    for (const torch::Tensor& index : shuffled_batches(data.features.count(), schedule.batch_size, context.generator)) {
      if (index.size(0) < 2) break;  // BatchNorm cannot train on a single sample
      const torch::Tensor loss = batch_loss(data.features.gather(index), data.labels.index_select(0, index));
      optimizer.zero_grad();
      loss.backward();
      optimizer.step();
      // A stop is honoured within an epoch too: on more threads than cores one epoch can take minutes.
      stop_if_requested();
      loss_sum += loss.item<double>();
      ++batches;
    }
    last_loss = batches > 0 ? loss_sum / batches : 0.0;
    context.log_epoch(phase, epoch + 1, schedule.epochs,
                      {{"loss", last_loss}, {"lr", optimizer.param_groups().front().options().get_lr()}});
    if (!keep_going(epoch + 1)) break;
  }
  return last_loss;
}

double train_supervised(ResNet18Encoder& encoder, CosineClassifier& classifier, const SessionData& data,
                        std::int64_t classes, const SupervisedSchedule& schedule, RunContext& context,
                        const std::string& phase) {
  std::vector<torch::Tensor> parameters = encoder->parameters();
  for (const auto& parameter : classifier->parameters()) parameters.push_back(parameter);
  encoder->train();
  classifier->train();
  const BatchLoss cross_entropy = [&](const torch::Tensor& features, const torch::Tensor& labels) {
    return torch::nn::functional::cross_entropy(classifier->forward(encoder->forward(features), classes), labels);
  };
  return train_epochs(parameters, cross_entropy, data, schedule, context, phase);
}

StageWork pretraining_work(const ParameterSet& read, const RunSizes& sizes) {
  return {"pretraining", static_cast<double>(SupervisedSchedule::from(read).epochs) * static_cast<double>(sizes.base_train)};
}

StageWork base_embedding_work(const RunSizes& sizes, int passes) {
  return {"base embeddings", 0, static_cast<double>(passes * sizes.base_train + sizes.base_validation)};
}

StageWork session_work(const RunSizes& sizes, double head_steps_per_session) {
  const double sessions = sizes.sessions - 1;
  return {"sessions", 0, sessions * sizes.way * sizes.shot, sessions * head_steps_per_session, false};
}

std::map<std::string, ParameterDefaults> pretraining_profiles(
    const std::map<std::string, ParameterDefaults>& later_stages) {
  std::map<std::string, ParameterDefaults> profiles = {{"smoke", {{"pretrain_epochs", "3"}, {"lr_step", "2"}}},
                                                       {"fast", {{"pretrain_epochs", "8"}, {"lr_step", "4"}}}};
  for (const auto& [profile, defaults] : later_stages) {
    profiles[profile].insert(profiles[profile].end(), defaults.begin(), defaults.end());
  }
  return profiles;
}

}  // namespace fscil
