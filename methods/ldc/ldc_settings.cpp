#include "methods/ldc/ldc_settings.h"

#include "core/parameter_set.h"

namespace fscil {

LdcSettings LdcSettings::from(const ParameterSet& params) {
  LdcSettings s;
  s.base = SupervisedSchedule::from(params);
  s.temperature = params.real("temperature", s.temperature, ValidRange::above(0));
  s.calibration_epochs =
      params.count("ldc_calibration_epochs", s.calibration_epochs, ValidRange::at_least(0));
  s.calibration_lr = params.real("ldc_calibration_lr", s.calibration_lr, ValidRange::at_least(0));
  s.calibration_rounds =
      params.count("ldc_calibration_rounds", s.calibration_rounds, ValidRange::at_least(1));
  s.calibration_samples =
      params.count("ldc_calibration_samples", s.calibration_samples, ValidRange::at_least(1));
  s.unit_rms = params.real("ldc_unit_rms", s.unit_rms, ValidRange::above(0));
  // A base class's replay is the first of its drawn features (Network.py L216), so it cannot ask for more.
  s.replay_samples = static_cast<int>(
      params.integer("ldc_replay_samples", s.replay_samples, ValidRange::between(1, s.calibration_samples)));
  s.session_epochs = params.count("ldc_session_epochs", s.session_epochs, ValidRange::at_least(0));
  s.session_lr = params.real("ldc_session_lr", s.session_lr, ValidRange::at_least(0));
  s.session_batch = params.count("ldc_session_batch", s.session_batch, ValidRange::at_least(1));
  return s;
}

}  // namespace fscil
