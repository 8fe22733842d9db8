#include "methods/comp_fscil/comp_settings.h"

#include "core/parameter_set.h"

namespace fscil {

CompSettings CompSettings::from(const ParameterSet& params) {
  CompSettings s;
  s.base = SupervisedSchedule::from(params);
  s.temperature = params.real("comp_temperature", s.temperature, ValidRange::above(0));
  s.vector_weight = params.real("comp_vector_weight", s.vector_weight, ValidRange::at_least(0));
  s.map_weight = params.real("comp_map_weight", s.map_weight, ValidRange::at_least(0));
  s.vector_power = params.real("comp_vector_power", s.vector_power, ValidRange::above(0));
  s.map_power = params.real("comp_map_power", s.map_power, ValidRange::above(0));
  s.reuse_tau = params.real("comp_reuse_tau", s.reuse_tau, ValidRange::at_least(0));
  s.reuse_weight = params.real("comp_reuse_weight", s.reuse_weight, ValidRange::at_least(0));
  s.map_temperature = params.real("comp_map_temperature", s.map_temperature, ValidRange::above(0));
  s.session_steps = params.count("comp_session_steps", s.session_steps, ValidRange::at_least(0));
  s.session_lr = params.real("comp_session_lr", s.session_lr, ValidRange::at_least(0));
  return s;
}

}  // namespace fscil
