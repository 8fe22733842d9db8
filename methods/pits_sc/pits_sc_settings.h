#pragma once
#include "methods/common/supervised_training.h"

namespace fscil {

class ParameterSet;

// PITS-SC's hyper-parameters as named options. Defaults are the CoP-FSCIL paper's tactile
// schedule (100/10/200 epochs, lr 0.1/0.01/0.1) and the released code's other values;
// LS-100 and NS-100 get the released configs through their dataset defaults.
struct PitsScSettings {
  SupervisedSchedule pretrain;  // stage A: pretrain_epochs, pretrain_lr, batch_size, ...
  double p_cutmix = 0.6;        // released LS-100 value (ours for tactile data: the paper is silent)
  double cutmix_alpha = 0.8;       // released pre_mixup_alpha
  bool cutmix_after_input_norm = true;  // cutmix_space=standardised (released: after bn0) | raw
  bool cutmix_loss_mixed = false;  // cutmix_loss=original (released) | mixed

  SupervisedSchedule pit;  // stage B: pit_epochs, pit_lr; the rest as stage A
  int pit_episodes = 50;
  int pit_way = 20;    // base classes per episode
  int pit_kept = 10;   // of which keep their labels; the others pair into pseudo-novel classes
  int pit_shot = 5;
  int pit_query = 15;
  double pit_alpha = 0.8;  // Beta(alpha, alpha) for the raw-signal mix (released LS-100 value)

  int epochs_new = 200;
  double lr_new = 0.1;
  double lamda_proto = 0.0;  // weight of CE on stored old-class means (released configs: 0)
  double temperature = 16.0;

  static PitsScSettings from(const ParameterSet& params);
};

}  // namespace fscil
