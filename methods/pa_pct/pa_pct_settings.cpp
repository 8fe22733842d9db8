#include "methods/pa_pct/pa_pct_settings.h"

#include "core/parameter_set.h"

namespace fscil {

PaPctSettings PaPctSettings::from(const ParameterSet& params) {
  PaPctSettings s;
  s.pcts_epochs = params.count("pa_pct_epochs", s.pcts_epochs, ValidRange::at_least(0));
  s.pcts_episodes = params.count("pa_pct_episodes", s.pcts_episodes, ValidRange::at_least(1));
  s.pcts_alpha = params.real("pa_pct_alpha", s.pcts_alpha, ValidRange::above(0));
  s.pcts_encoder_lr = params.real("pa_pct_encoder_lr", s.pcts_encoder_lr, ValidRange::at_least(0));
  s.pcts_attention_lr = params.real("pa_pct_attention_lr", s.pcts_attention_lr, ValidRange::at_least(0));
  s.session_attention_lr = params.real("pa_pct_session_lr", s.session_attention_lr, ValidRange::at_least(0));
  return s;
}

}  // namespace fscil
