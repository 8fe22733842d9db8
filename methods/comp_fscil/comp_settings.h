#pragma once
#include "methods/common/supervised_training.h"

namespace fscil {

class ParameterSet;

// Comp-FSCIL's hyper-parameters as named options. Defaults are the README's miniImageNet command
// with its ResNet-12 (Zoilsen/Comp-FSCIL README.md L33 at 95a44177), chosen on validation over the
// same dataset's ResNet-18 command (L38); docs/methods.md gives each line and the numbers.
struct CompSettings {
  SupervisedSchedule base;         // the shared pretraining schedule every method here gets
  double temperature = 1;          // comp_temperature: the vector head's T (-temperature)
  double vector_weight = 1;        // comp_vector_weight (-backbone_feat_cls_weight)
  double map_weight = 2;           // comp_map_weight: the CKA head's CE (-map_metric_cls_w)
  double vector_power = 1.1;       // comp_vector_power: signed power of the pooled vector (-bkb_feat_pow)
  double map_power = 0.8;          // comp_map_power: signed power of the sample's map (-map_pow)
  double reuse_tau = 64;           // comp_reuse_tau: sharpness of the primitive reuse (-aux_param)
  double reuse_weight = 4;         // comp_reuse_weight (-primitive_recon_cls_weight)
  double map_temperature = 16;     // comp_map_temperature: the learned CKA scale's start (Network.py L53-L57)
  int session_steps = 100;         // comp_session_steps (-epochs_new, train.py L20)
  double session_lr = 0.1;         // comp_session_lr (-lr_new)

  static CompSettings from(const ParameterSet& params);
};

}  // namespace fscil
