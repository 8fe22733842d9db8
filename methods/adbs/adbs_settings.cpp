#include "methods/adbs/adbs_settings.h"

#include "core/parameter_set.h"

namespace fscil {

AdbsSettings AdbsSettings::from(const ParameterSet& params) {
  AdbsSettings s;
  s.base = SupervisedSchedule::from(params);
  s.temperature = params.real("temperature", s.temperature, ValidRange::above(0));
  s.constraint_weight = params.real("adbs_constraint_weight", s.constraint_weight, ValidRange::at_least(0));
  s.session_steps = params.count("adbs_session_steps", s.session_steps, ValidRange::at_least(0));
  s.session_lr = params.real("adbs_session_lr", s.session_lr, ValidRange::at_least(0));
  return s;
}

}  // namespace fscil
