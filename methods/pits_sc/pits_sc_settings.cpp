#include "methods/pits_sc/pits_sc_settings.h"

#include <fmt/format.h>

#include "protocols/parameter_set.h"

namespace fscil {

PitsScSettings PitsScSettings::from(const ParameterSet& params) {
  PitsScSettings s;
  s.pretrain = SupervisedSchedule::from(params);
  s.p_cutmix = params.real("p_cutmix", s.p_cutmix);
  s.cutmix_alpha = params.real("cutmix_alpha", s.cutmix_alpha);
  s.cutmix_after_input_norm = params.choice("cutmix_space", "standardised", {"standardised", "raw"}) == "standardised";
  s.cutmix_loss_mixed = params.choice("cutmix_loss", "original", {"original", "mixed"}) == "mixed";

  s.pit = s.pretrain;
  s.pit.epochs = static_cast<int>(params.integer("pit_epochs", 10));
  s.pit.learning_rate = params.real("pit_lr", 0.01);
  s.pit_episodes = static_cast<int>(params.integer("pit_episodes", s.pit_episodes));
  s.pit_way = static_cast<int>(params.integer("pit_way", s.pit_way));
  s.pit_kept = static_cast<int>(params.integer("pit_kept", s.pit_kept));
  s.pit_shot = static_cast<int>(params.integer("pit_shot", s.pit_shot));
  s.pit_query = static_cast<int>(params.integer("pit_query", s.pit_query));
  s.pit_alpha = params.real("pit_alpha", s.pit_alpha);

  s.epochs_new = static_cast<int>(params.integer("epochs_new", s.epochs_new));
  s.lr_new = params.real("lr_new", s.lr_new);
  s.lamda_proto = params.real("lamda_proto", s.lamda_proto);
  s.temperature = params.real("temperature", s.temperature);

  if (s.p_cutmix < 0 || s.p_cutmix > 1 || s.cutmix_alpha <= 0 || s.pit_alpha <= 0 || s.lamda_proto < 0 ||
      s.lamda_proto > 1) {
    throw MethodError(fmt::format("p_cutmix={} cutmix_alpha={} pit_alpha={} lamda_proto={}: expected p_cutmix and "
                                  "lamda_proto in [0, 1] and positive alphas",
                                  s.p_cutmix, s.cutmix_alpha, s.pit_alpha, s.lamda_proto));
  }
  if (s.pit.epochs < 0 || s.pit_episodes < 1 || s.pit_kept < 1 || s.pit_way <= s.pit_kept ||
      (s.pit_way - s.pit_kept) % 2 != 0 || s.pit_shot < 1 || s.pit_query < 1 || s.epochs_new < 0 || s.lr_new <= 0) {
    throw MethodError(fmt::format("pit_epochs={} pit_episodes={} pit_way={} pit_kept={} pit_shot={} pit_query={} "
                                  "epochs_new={} lr_new={}: expected pit_way - pit_kept positive and even, counts "
                                  ">= 1, epochs >= 0, lr_new > 0",
                                  s.pit.epochs, s.pit_episodes, s.pit_way, s.pit_kept, s.pit_shot, s.pit_query,
                                  s.epochs_new, s.lr_new));
  }
  return s;
}

}  // namespace fscil
