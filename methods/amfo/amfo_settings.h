#pragma once
#include <cstdint>

#include "methods/common/supervised_training.h"

namespace fscil {

class ParameterSet;

// AMFO's hyper-parameters as named options. Defaults are the release's LS-100 run
// (Jialongdustin/AMFO run_librispeech.sh at d16e9e10, train.py at 4620fab6, Inc_train.py at
// 26b2d3f2, models/AMFO.py at 7ea36354); docs/methods.md gives each line. The base schedule is the
// shared pretraining schedule every method here gets.
struct AmfoSettings {
  SupervisedSchedule base;
  double temperature = 16;         // the fused and binary logits' scale, a literal (train.py L134, Inc_train.py L451)
  double cosface_scale = 32;       // amfo_cosface_scale: s of both CosFace losses (AMFO.py L130-L131)
  double positive_margin = 0.1;    // amfo_positive_margin: the deep head's margin, m_p (AMFO.py L21)
  double negative_margin = -0.5;   // amfo_negative_margin: the other head's, m_n (AMFO.py L22)
  double base_fusion_weight = 2.5;   // amfo_base_fusion_weight: --weight_atten (train.py L39)
  double base_margin_weight = 1;     // amfo_base_margin_weight: 1 for LS-100 (train.py L91)
  double base_binary_weight = 40;    // amfo_base_binary_weight: --weight_binary (train.py L41)
  double session_fusion_weight = 10;   // amfo_session_fusion_weight (Inc_train.py L53)
  double session_margin_weight = 2;    // amfo_session_margin_weight (Inc_train.py L54)
  double session_binary_weight = 0.4;  // amfo_session_binary_weight (Inc_train.py L55)
  double gamma = 0.2;              // amfo_gamma: weight of fc1's path beside a session's support (run L2)
  double sparsity_floor = 0;       // amfo_r: the gate penalty's floor r; the release's is a parameter at 0 (AMFO.py L41)
  std::int64_t fusion_hidden = 64;  // the BinaryNet's hidden width (binary_net.py L10)
  int session_epochs = 130;        // amfo_session_epochs (--max_epoch, run L2)
  double session_lr = 0.1;         // amfo_session_lr (--lr)
  int session_batch = 256;         // amfo_session_batch (--batch_size)
  int refresh_every = 2;           // amfo_refresh_every: epochs between redraws (--delay_estimation)
  int new_samples = 5;             // amfo_new_samples: draws per current class (--newsample_num)
  int old_samples = 10;            // amfo_old_samples: draws per older class, max(5, --sample_k 10) (exemplar.py L59-L73)

  static AmfoSettings from(const ParameterSet& params);
};

}  // namespace fscil
