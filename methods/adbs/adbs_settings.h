#pragma once
#include "methods/common/supervised_training.h"

namespace fscil {

class ParameterSet;

// ADBS's hyper-parameters as named options. Defaults are the released code's
// (Yongzhang-Tan/ADBS train.py at 756414c3); docs/methods.md gives each line.
struct AdbsSettings {
  SupervisedSchedule base;   // the shared pretraining schedule every method here gets (pretrain_epochs, ...)
  double temperature = 16;   // cosine scale (train.py L33)
  double constraint_weight = 0.01;  // adbs_constraint_weight: the IC loss's weight (reg_alpha, L72)
  int session_steps = 10;           // adbs_session_steps: margin updates per session (epochs_new_train, L67)
  double session_lr = 0.1;          // adbs_session_lr (lr_new, L23)

  static AdbsSettings from(const ParameterSet& params);
};

}  // namespace fscil
