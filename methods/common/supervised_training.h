#pragma once
#include <functional>
#include <string>
#include <vector>

#include "methods/common/cosine_classifier.h"
#include "methods/common/resnet18.h"
#include "methods/common/stage_progress.h"
#include "methods/method.h"
#include "methods/method_registry.h"

namespace fscil {

// How the learning rate falls over a schedule: by lr_gamma every lr_step epochs (PITS-SC), or by
// a cosine over every optimiser step to 0 (lr_t = lr (1 + cos(pi t / steps)) / 2, t = 0 .. steps - 1,
// ARP's release: chester-w-xie/APR Utils.py L130-L137).
enum class LearningRateDecay { step, cosine };

// SGD with Nesterov momentum and a step learning-rate decay, as PITS-SC pretrains. A method whose
// release trains otherwise passes its own defaults to from() (ARP: plain SGD, cosine).
struct SupervisedSchedule {
  int epochs = 100;
  double learning_rate = 0.1;
  int batch_size = 128;
  double momentum = 0.9;
  bool nesterov = true;  // with a momentum above 0 only (PyTorch refuses Nesterov without one)
  double weight_decay = 5e-4;
  LearningRateDecay decay = LearningRateDecay::step;  // lr_decay=step | cosine
  int lr_step = 40;  // epochs between decays (step only)
  double lr_gamma = 0.5;
  // base_stop=converged: a stage that scores base validation ends once it has converged on a plateau
  // (metrics/convergence.h, stage_has_levelled_off), `epochs` its cap; base_stop=schedule runs them all.
  bool stop_when_converged = false;

  // Reads pretrain_epochs, pretrain_lr, batch_size, momentum, weight_decay, lr_decay, base_stop,
  // and for the step decay lr_step and lr_gamma, each defaulting to `defaults`' value.
  static SupervisedSchedule from(const ParameterSet& params, const SupervisedSchedule& defaults);
  static SupervisedSchedule from(const ParameterSet& params) { return from(params, SupervisedSchedule()); }
  // The learning rate of optimiser step `step` (0-based) of epoch `epoch` (0-based), of
  // `steps_per_epoch`.
  double rate_at(int epoch, std::int64_t step, std::int64_t steps_per_epoch) const;
  // The epochs plan's estimate counts: all of them, or under stop_when_converged the epoch such
  // stages typically stopped at (kTypicalConvergedEpoch), within the cap.
  double expected_epochs() const;
};

// Where base_stop=converged stages stopped under the fast profile, for plan's sum of times: the
// mean of the first 15 stops measured on simtex and sf-instruments (12.5); the 21 stops measured
// since have a mean of 13.0 and a median of 12 (docs/methods.md, "The fast profile"). An estimate,
// not a schedule.
inline constexpr int kTypicalConvergedEpoch = 12;

// Work of the stages most methods share (MethodEntry::work): expected_epochs() passes over the base
// training samples and as many scorings of base validation; embedding the base training samples
// `passes` times after training (class rows, Gaussians) and the validation samples once; each
// incremental session embedding its shots and taking `head_steps` optimiser steps on them.
StageWork pretraining_work(const ParameterSet& read, const RunSizes& sizes);
StageWork base_embedding_work(const RunSizes& sizes, int passes = 1);
StageWork session_work(const RunSizes& sizes, double head_steps_per_session);

// SGD with the schedule's momentum (Nesterov where it says so) and weight decay, at its initial
// learning rate.
torch::optim::SGD make_schedule_sgd(const std::vector<torch::Tensor>& parameters, const SupervisedSchedule& schedule);
// Sets the learning rate of step `step` of `epoch` (0-based; SupervisedSchedule::rate_at).
void set_learning_rate(torch::optim::SGD& optimizer, const SupervisedSchedule& schedule, int epoch,
                       std::int64_t step, std::int64_t steps_per_epoch);

// Under stop_when_converged: whether `phase` has levelled off after its epoch `epoch` (1-based) on
// the base validation it logged (metrics/convergence.h), recording `<phase>_converged_epoch` when
// it has. Every stage that stops by base_stop=converged asks here.
bool stop_once_levelled_off(const SupervisedSchedule& schedule, RunContext& context, const std::string& phase,
                            int epoch);
// The same where the stage stops by another test than its schedule's (`may_stop`: OrCo's projector
// from its released epochs on).
bool stop_once_levelled_off(bool may_stop, RunContext& context, const std::string& phase, int epoch);

// The loss of one mini-batch (features and labels already gathered).
using BatchLoss = std::function<torch::Tensor(const torch::Tensor& features, const torch::Tensor& labels)>;

// Epochs of shuffled mini-batches over `data` with the schedule's optimiser and step decay,
// minimising `batch_loss` over `parameters`. Modules must already be in the wanted mode. Each
// epoch is logged (RunContext::log_epoch), then `after_epoch` is called with its 1-based number.
// Under stop_when_converged the stage ends once the base validation `after_epoch` records has
// converged (diagnostic `<phase>_converged_epoch`). With a `keeping`, the stage keeps its progress
// and continues from what an earlier process of the run kept (stage_progress.h). Returns the mean
// loss of the last epoch.
double train_epochs(const std::vector<torch::Tensor>& parameters, const BatchLoss& batch_loss, const SessionData& data,
                    const SupervisedSchedule& schedule, RunContext& context, const std::string& phase,
                    const std::function<void(int)>& after_epoch = {}, const StageKeeping& keeping = {});
// The same, stopping early once `keep_going` (called after each epoch with its 1-based number, in
// place of `after_epoch`) returns false: the schedule's later epochs are then never run.
double train_epochs_while(const std::vector<torch::Tensor>& parameters, const BatchLoss& batch_loss,
                          const SessionData& data, const SupervisedSchedule& schedule, RunContext& context,
                          const std::string& phase, const std::function<bool(int)>& keep_going,
                          const StageKeeping& keeping = {});

// Cross-entropy training of encoder + cosine classifier on the classes [0, classes) of `data`.
// Returns the mean loss of the last epoch.
double train_supervised(ResNet18Encoder& encoder, CosineClassifier& classifier, const SessionData& data,
                        std::int64_t classes, const SupervisedSchedule& schedule, RunContext& context,
                        const std::string& phase);

// How the profiles shorten this pretraining (MethodEntry::profile_defaults). smoke: 3 epochs, the
// learning-rate step with them so that the decay still happens. fast: the stage runs until its base
// validation has levelled off (base_stop=converged), at most 40 epochs with the rate halved every 4,
// so that no method is judged on a training still rising (docs/methods.md, "The fast profile").
// Then, per profile, `later_stages`: how it shortens the stages a method trains after the pretraining.
std::map<std::string, ParameterDefaults> pretraining_profiles(
    const std::map<std::string, ParameterDefaults>& later_stages = {});

}  // namespace fscil
