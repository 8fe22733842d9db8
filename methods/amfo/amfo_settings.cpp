#include "methods/amfo/amfo_settings.h"

#include "core/parameter_set.h"

namespace fscil {

AmfoSettings AmfoSettings::from(const ParameterSet& params) {
  AmfoSettings s;
  s.base = SupervisedSchedule::from(params);
  s.cosface_scale = params.real("amfo_cosface_scale", s.cosface_scale, ValidRange::above(0));
  s.positive_margin = params.real("amfo_positive_margin", s.positive_margin, ValidRange::any());
  s.negative_margin = params.real("amfo_negative_margin", s.negative_margin, ValidRange::any());
  s.base_fusion_weight = params.real("amfo_base_fusion_weight", s.base_fusion_weight, ValidRange::at_least(0));
  s.base_margin_weight = params.real("amfo_base_margin_weight", s.base_margin_weight, ValidRange::at_least(0));
  s.base_binary_weight = params.real("amfo_base_binary_weight", s.base_binary_weight, ValidRange::at_least(0));
  s.session_fusion_weight = params.real("amfo_session_fusion_weight", s.session_fusion_weight, ValidRange::at_least(0));
  s.session_margin_weight = params.real("amfo_session_margin_weight", s.session_margin_weight, ValidRange::at_least(0));
  s.session_binary_weight = params.real("amfo_session_binary_weight", s.session_binary_weight, ValidRange::at_least(0));
  s.gamma = params.real("amfo_gamma", s.gamma, ValidRange::at_least(0));
  s.sparsity_floor = params.real("amfo_r", s.sparsity_floor, ValidRange::at_least(0));
  s.session_epochs = params.count("amfo_session_epochs", s.session_epochs, ValidRange::at_least(0));
  s.session_lr = params.real("amfo_session_lr", s.session_lr, ValidRange::at_least(0));
  s.session_batch = params.count("amfo_session_batch", s.session_batch, ValidRange::at_least(1));
  s.refresh_every = params.count("amfo_refresh_every", s.refresh_every, ValidRange::at_least(1));
  s.new_samples = params.count("amfo_new_samples", s.new_samples, ValidRange::at_least(0));
  s.old_samples = params.count("amfo_old_samples", s.old_samples, ValidRange::at_least(0));
  return s;
}

}  // namespace fscil
