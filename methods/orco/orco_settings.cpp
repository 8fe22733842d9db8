#include "methods/orco/orco_settings.h"

#include <algorithm>
#include <cmath>

#include "core/named_choice.h"
#include "core/parameter_set.h"

namespace fscil {

double ProjectorSchedule::rate_at(int epoch) const {
  if (decay == ProjectorDecay::milestone) return learning_rate * std::pow(0.1, (epoch >= 60) + (epoch >= 80));
  const int warmup = std::min(warmup_epochs, epochs);
  if (epoch < warmup) return warmup_start + epoch * (learning_rate - warmup_start) / std::max(1, warmup - 1);
  return final_rate +
         (learning_rate - final_rate) * (1.0 + std::cos(M_PI * (epoch - warmup) / (epochs - warmup))) / 2.0;
}

OrcoSettings OrcoSettings::from(const ParameterSet& params) {
  OrcoSettings s;
  s.pretrain = SupervisedSchedule::from(params);
  s.temperature = params.real("temperature", s.temperature, ValidRange::above(0));
  s.projector_hidden = params.integer("orco_projector_hidden", s.projector_hidden, ValidRange::at_least(1));
  s.projection_size = params.integer("orco_projection_size", s.projection_size, ValidRange::at_least(2));
  s.target_steps = params.count("orco_target_steps", s.target_steps, ValidRange::at_least(0));
  s.target_lr = params.real("orco_target_lr", s.target_lr, ValidRange::above(0));
  s.supcon_temperature = params.real("orco_supcon_temperature", s.supcon_temperature, ValidRange::above(0));
  s.perturb_epsilon = params.real("orco_perturb_epsilon", s.perturb_epsilon, ValidRange::at_least(0));
  s.perturb_offset = params.real("orco_perturb_offset", s.perturb_offset, ValidRange::at_least(0));

  s.base.epochs = params.count("orco_base_epochs", s.base.epochs, ValidRange::at_least(0));
  s.base.learning_rate = params.real("orco_base_lr", s.base.learning_rate, ValidRange::above(0));
  s.base.batch_size =
      params.count("orco_base_batch", s.pretrain.batch_size, ValidRange::at_least(2));
  s.base.decay = named_choice(params, "orco_base_schedule", s.base.decay,
                              {{"milestone", ProjectorDecay::milestone}, {"cosine", ProjectorDecay::cosine}});
  if (s.pretrain.stop_when_converged) {
    // Read only here, so that a schedule-length run's identity stays what it was.
    s.base_epochs_cap = params.count("orco_base_epochs_cap", s.base_epochs_cap, ValidRange::at_least(1));
    if (s.base.epochs > 0) {
      s.base.levelled_off_stop_from = s.base.epochs;
      s.base.epochs = std::max(s.base.epochs, s.base_epochs_cap);
    }
  }
  s.session.epochs = params.count("orco_session_epochs", s.session.epochs, ValidRange::at_least(0));
  s.session.learning_rate = params.real("orco_session_lr", s.session.learning_rate, ValidRange::above(0));
  s.session.batch_size =
      params.count("orco_session_batch", s.session.batch_size, ValidRange::at_least(2));
  s.session.warmup_epochs =
      params.count("orco_session_warmup", s.session.warmup_epochs, ValidRange::at_least(0));
  s.session_stop.on_validation =
      named_choice(params, "orco_session_stop", s.session_stop.on_validation, {{"validation", true}, {"last", false}});
  s.session_stop.check_every =
      params.count("orco_session_check", s.session_stop.check_every, ValidRange::at_least(1));
  s.session_stop.patience =
      params.count("orco_session_patience", s.session_stop.patience, ValidRange::at_least(1));
  s.novel_ce_weight = params.real("orco_novel_ce_weight", s.novel_ce_weight, ValidRange::at_least(0));
  s.base_ce_weight = params.real("orco_base_ce_weight", s.base_ce_weight, ValidRange::at_least(0));
  s.session_orthogonality_novel_only = named_choice(params, "orco_session_orthogonality",
                                                    s.session_orthogonality_novel_only,
                                                    {{"novel", true}, {"all", false}});

  s.exemplars_per_base_class =
      params.count("orco_exemplars", s.exemplars_per_base_class, ValidRange::at_least(0));
  s.exemplar_source = named_choice(params, "orco_exemplars_from", s.exemplar_source,
                                   {{"recordings", ExemplarSource::recordings}, {"first", ExemplarSource::first}});
  s.views = params.count("orco_views", s.views, ValidRange::at_least(2));
  s.mask_time_fraction = params.real("orco_mask_time", s.mask_time_fraction, ValidRange::from_up_to(0, 1));
  s.mask_mel_fraction = params.real("orco_mask_mel", s.mask_mel_fraction, ValidRange::from_up_to(0, 1));

  return s;
}

}  // namespace fscil
