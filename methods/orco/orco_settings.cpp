#include "methods/orco/orco_settings.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "methods/method.h"
#include "protocols/parameter_set.h"

namespace fscil {

namespace {

void check_schedule(const ProjectorSchedule& schedule, const char* prefix) {
  if (schedule.epochs < 0 || schedule.learning_rate <= 0 || schedule.final_rate < 0 || schedule.weight_decay < 0 ||
      schedule.batch_size < 2) {
    throw MethodError(fmt::format("{}_epochs={} {}_lr={} {}_batch={}: expected epochs >= 0, a positive learning "
                                  "rate and batches of at least 2",
                                  prefix, schedule.epochs, prefix, schedule.learning_rate, prefix,
                                  schedule.batch_size));
  }
}

}  // namespace

double ProjectorSchedule::rate_at(int epoch) const {
  const int warmup = std::min(warmup_epochs, epochs);
  if (epoch < warmup) return warmup_start + epoch * (learning_rate - warmup_start) / std::max(1, warmup - 1);
  return final_rate +
         (learning_rate - final_rate) * (1.0 + std::cos(M_PI * (epoch - warmup) / (epochs - warmup))) / 2.0;
}

OrcoSettings OrcoSettings::from(const ParameterSet& params) {
  OrcoSettings s;
  s.pretrain = SupervisedSchedule::from(params);
  s.temperature = params.real("temperature", s.temperature);
  s.projector_hidden = params.integer("orco_projector_hidden", s.projector_hidden);
  s.projection_size = params.integer("orco_projection_size", s.projection_size);
  s.target_steps = static_cast<int>(params.integer("orco_target_steps", s.target_steps));
  s.target_lr = params.real("orco_target_lr", s.target_lr);
  s.supcon_temperature = params.real("orco_supcon_temperature", s.supcon_temperature);
  s.perturb_epsilon = params.real("orco_perturb_epsilon", s.perturb_epsilon);
  s.perturb_offset = params.real("orco_perturb_offset", s.perturb_offset);

  s.base.epochs = static_cast<int>(params.integer("orco_base_epochs", s.base.epochs));
  s.base.learning_rate = params.real("orco_base_lr", s.base.learning_rate);
  s.base.batch_size = static_cast<int>(params.integer("orco_base_batch", s.pretrain.batch_size));
  s.session.epochs = static_cast<int>(params.integer("orco_session_epochs", s.session.epochs));
  s.session.learning_rate = params.real("orco_session_lr", s.session.learning_rate);
  s.session.batch_size = static_cast<int>(params.integer("orco_session_batch", s.session.batch_size));
  s.session.warmup_epochs = static_cast<int>(params.integer("orco_session_warmup", s.session.warmup_epochs));
  s.session_stop.on_validation = params.choice("orco_session_stop", "validation", {"validation", "last"}) == "validation";
  s.session_stop.check_every = static_cast<int>(params.integer("orco_session_check", s.session_stop.check_every));
  s.session_stop.patience = static_cast<int>(params.integer("orco_session_patience", s.session_stop.patience));
  s.novel_ce_weight = params.real("orco_novel_ce_weight", s.novel_ce_weight);
  s.base_ce_weight = params.real("orco_base_ce_weight", s.base_ce_weight);
  s.session_orthogonality_novel_only =
      params.choice("orco_session_orthogonality", "novel", {"novel", "all"}) == "novel";

  s.exemplars_per_base_class = static_cast<int>(params.integer("orco_exemplars", s.exemplars_per_base_class));
  s.exemplar_source = params.choice("orco_exemplars_from", "recordings", {"recordings", "first"}) == "first"
                          ? ExemplarSource::first
                          : ExemplarSource::recordings;
  s.views = static_cast<int>(params.integer("orco_views", s.views));
  s.mask_time_fraction = params.real("orco_mask_time", s.mask_time_fraction);
  s.mask_mel_fraction = params.real("orco_mask_mel", s.mask_mel_fraction);

  check_schedule(s.base, "orco_base");
  check_schedule(s.session, "orco_session");
  if (s.projector_hidden < 1 || s.projection_size < 2 || s.target_steps < 0 || s.target_lr <= 0 ||
      s.supcon_temperature <= 0 || s.perturb_epsilon < 0 || s.novel_ce_weight < 0 || s.base_ce_weight < 0) {
    throw MethodError(fmt::format("orco_projector_hidden={} orco_projection_size={} orco_target_steps={} "
                                  "orco_target_lr={} orco_supcon_temperature={} orco_perturb_epsilon={} "
                                  "orco_novel_ce_weight={} orco_base_ce_weight={}: expected positive sizes and "
                                  "rates, steps, epsilon and weights >= 0",
                                  s.projector_hidden, s.projection_size, s.target_steps, s.target_lr,
                                  s.supcon_temperature, s.perturb_epsilon, s.novel_ce_weight, s.base_ce_weight));
  }
  if (s.session.warmup_epochs < 0 || s.session_stop.check_every < 1 || s.session_stop.patience < 1) {
    throw MethodError(fmt::format("orco_session_warmup={} orco_session_check={} orco_session_patience={}: expected "
                                  "a warmup >= 0 and checks and patience of at least 1",
                                  s.session.warmup_epochs, s.session_stop.check_every, s.session_stop.patience));
  }
  if (s.exemplars_per_base_class < 0 || s.views < 2 || s.mask_time_fraction < 0 || s.mask_time_fraction >= 1 ||
      s.mask_mel_fraction < 0 || s.mask_mel_fraction >= 1) {
    throw MethodError(fmt::format("orco_exemplars={} orco_views={} orco_mask_time={} orco_mask_mel={}: expected "
                                  "exemplars >= 0, at least 2 views and mask shares in [0, 1)",
                                  s.exemplars_per_base_class, s.views, s.mask_time_fraction, s.mask_mel_fraction));
  }
  return s;
}

}  // namespace fscil
