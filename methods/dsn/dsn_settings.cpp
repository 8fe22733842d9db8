#include "methods/dsn/dsn_settings.h"

#include "core/parameter_set.h"

namespace fscil {

DsnSettings DsnSettings::from(const ParameterSet& params) {
  DsnSettings s;
  s.base = SupervisedSchedule::from(params);
  s.temperature = params.real("temperature", s.temperature, ValidRange::above(0));
  s.nodes = params.integer("dsn_nodes", s.nodes, ValidRange::at_least(0));
  s.gamma = params.real("dsn_gamma", s.gamma, ValidRange::at_least(0));
  s.session_epochs = params.count("dsn_session_epochs", s.session_epochs, ValidRange::at_least(0));
  s.session_lr = params.real("dsn_session_lr", s.session_lr, ValidRange::at_least(0));
  s.session_batch = params.count("dsn_session_batch", s.session_batch, ValidRange::at_least(1));
  s.refresh_every = params.count("dsn_refresh_every", s.refresh_every, ValidRange::at_least(1));
  s.new_samples = params.count("dsn_new_samples", s.new_samples, ValidRange::at_least(0));
  s.old_samples = params.count("dsn_old_samples", s.old_samples, ValidRange::at_least(0));
  s.base_samples = params.count("dsn_base_samples", s.base_samples, ValidRange::at_least(0));
  s.sample_k = params.count("dsn_sample_k", s.sample_k, ValidRange::at_least(0));
  s.top_k = params.count("dsn_top_k", s.top_k, ValidRange::at_least(0));
  return s;
}

}  // namespace fscil
