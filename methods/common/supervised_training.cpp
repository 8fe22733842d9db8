#include "methods/common/supervised_training.h"

#include <algorithm>
#include <cmath>

#include "core/named_choice.h"
#include "core/stop_request.h"
#include "methods/common/embedding.h"
#include "methods/common/epoch_validation.h"
#include "methods/common/shuffled_batches.h"

namespace fscil {

SupervisedSchedule SupervisedSchedule::from(const ParameterSet& params, const SupervisedSchedule& defaults) {
  SupervisedSchedule schedule = defaults;
  schedule.epochs = params.count("pretrain_epochs", schedule.epochs, ValidRange::at_least(0));
  schedule.learning_rate = params.real("pretrain_lr", schedule.learning_rate, ValidRange::above(0));
  schedule.batch_size = params.count("batch_size", schedule.batch_size, ValidRange::at_least(2));
  schedule.momentum = params.real("momentum", schedule.momentum, ValidRange::from_up_to(0, 1));
  schedule.weight_decay = params.real("weight_decay", schedule.weight_decay, ValidRange::at_least(0));
  schedule.decay = named_choice(params, "lr_decay", schedule.decay,
                                {{"step", LearningRateDecay::step}, {"cosine", LearningRateDecay::cosine}});
  schedule.stop_when_converged =
      named_choice(params, "base_stop", schedule.stop_when_converged, {{"schedule", false}, {"converged", true}});
  if (schedule.decay == LearningRateDecay::step) {
    schedule.lr_step = params.count("lr_step", schedule.lr_step, ValidRange::at_least(1));
    schedule.lr_gamma = params.real("lr_gamma", schedule.lr_gamma, ValidRange::above_up_to(0, 1));
  }
  return schedule;
}

double SupervisedSchedule::rate_at(int epoch, std::int64_t step, std::int64_t steps_per_epoch) const {
  if (decay == LearningRateDecay::step) return learning_rate * std::pow(lr_gamma, epoch / lr_step);
  const double steps = static_cast<double>(epochs) * static_cast<double>(steps_per_epoch);
  const double t = static_cast<double>(epoch) * static_cast<double>(steps_per_epoch) + static_cast<double>(step);
  return 0.5 * learning_rate * (1 + std::cos(M_PI * t / steps));
}

double SupervisedSchedule::expected_epochs() const {
  return stop_when_converged ? std::min(epochs, kTypicalConvergedEpoch) : epochs;
}

torch::optim::SGD make_schedule_sgd(const std::vector<torch::Tensor>& parameters, const SupervisedSchedule& schedule) {
  return torch::optim::SGD(parameters, torch::optim::SGDOptions(schedule.learning_rate)
                                           .momentum(schedule.momentum)
                                           .nesterov(schedule.nesterov && schedule.momentum > 0)
                                           .weight_decay(schedule.weight_decay));
}

void set_learning_rate(torch::optim::SGD& optimizer, const SupervisedSchedule& schedule, int epoch, std::int64_t step,
                       std::int64_t steps_per_epoch) {
  const double rate = schedule.rate_at(epoch, step, steps_per_epoch);
  for (auto& group : optimizer.param_groups()) static_cast<torch::optim::SGDOptions&>(group.options()).lr(rate);
}

bool stop_once_levelled_off(const SupervisedSchedule& schedule, RunContext& context, const std::string& phase,
                            int epoch) {
  return stop_once_levelled_off(schedule.stop_when_converged, context, phase, epoch);
}

bool stop_once_levelled_off(bool may_stop, RunContext& context, const std::string& phase, int epoch) {
  if (!may_stop || !stage_has_levelled_off(context.training_log, phase)) return false;
  context.diagnostics[phase + "_converged_epoch"] = epoch;
  return true;
}

double train_epochs(const std::vector<torch::Tensor>& parameters, const BatchLoss& batch_loss, const SessionData& data,
                    const SupervisedSchedule& schedule, RunContext& context, const std::string& phase,
                    const std::function<void(int)>& after_epoch, const StageKeeping& keeping) {
  return train_epochs_while(
      parameters, batch_loss, data, schedule, context, phase,
      [&](int epoch) {
        if (after_epoch) after_epoch(epoch);
        return true;
      },
      keeping);
}

double train_epochs_while(const std::vector<torch::Tensor>& parameters, const BatchLoss& batch_loss,
                          const SessionData& data, const SupervisedSchedule& schedule, RunContext& context,
                          const std::string& phase, const std::function<bool(int)>& keep_going,
                          const StageKeeping& keeping) {
  torch::optim::SGD optimizer = make_schedule_sgd(parameters, schedule);
  const std::int64_t samples = data.features.count();
  const std::int64_t steps_per_epoch = (samples + schedule.batch_size - 1) / schedule.batch_size;
  const StageResumption resumed = resume_stage(phase, schedule.epochs, keeping, optimizer, context);
  if (resumed.finished) return resumed.last_loss;
  double last_loss = resumed.last_loss;
  for (int epoch = resumed.epochs_done; epoch < schedule.epochs; ++epoch) {
    double loss_sum = 0;
    std::int64_t batches = 0;
    for (const torch::Tensor& index : shuffled_batches(samples, schedule.batch_size, context.generator)) {
      if (index.size(0) < 2) break;  // BatchNorm cannot train on a single sample
      set_learning_rate(optimizer, schedule, epoch, batches, steps_per_epoch);
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
    const bool ends = !keep_going(epoch + 1) || stop_once_levelled_off(schedule, context, phase, epoch + 1) ||
                      epoch + 1 == schedule.epochs;
    keep_stage_progress(phase, keeping, optimizer, {epoch + 1, ends, last_loss}, context);
    if (ends) break;
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
  // What it trains is the base classifier's stage: base validation by the trained rows, every epoch.
  return train_epochs(parameters, cross_entropy, data, schedule, context, phase, [&](int) {
    record_epoch_validation(context, [&](const SessionData& scored) {
      return classifier->forward(embed_in_batches(encoder, scored.features), classes);
    });
  });
}

StageWork pretraining_work(const ParameterSet& read, const RunSizes& sizes) {
  const double epochs = SupervisedSchedule::from(read).expected_epochs();
  return {"pretraining", epochs * static_cast<double>(sizes.base_train), epochs * static_cast<double>(sizes.base_validation)};
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
                                                       {"fast", {{"pretrain_epochs", "40"}, {"lr_step", "4"}, {"base_stop", "converged"}}}};
  for (const auto& [profile, defaults] : later_stages) {
    profiles[profile].insert(profiles[profile].end(), defaults.begin(), defaults.end());
  }
  return profiles;
}

}  // namespace fscil
