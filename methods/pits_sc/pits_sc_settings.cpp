#include "methods/pits_sc/pits_sc_settings.h"

#include <fmt/format.h>

#include "core/named_choice.h"
#include "core/parameter_set.h"

namespace fscil {

PitsScSettings PitsScSettings::from(const ParameterSet& params) {
  PitsScSettings s;
  s.pretrain = SupervisedSchedule::from(params);
  s.p_cutmix = params.real("p_cutmix", s.p_cutmix, ValidRange::between(0, 1));
  s.cutmix_alpha = params.real("cutmix_alpha", s.cutmix_alpha, ValidRange::above(0));
  s.cutmix_after_input_norm =
      named_choice(params, "cutmix_space", s.cutmix_after_input_norm, {{"standardised", true}, {"raw", false}});
  s.cutmix_loss_mixed =
      named_choice(params, "cutmix_loss", s.cutmix_loss_mixed, {{"original", false}, {"mixed", true}});

  s.pit = s.pretrain;
  s.pit.epochs = params.count("pit_epochs", 10, ValidRange::at_least(0));
  s.pit.learning_rate = params.real("pit_lr", 0.01, ValidRange::above(0));
  s.pit_episodes = params.count("pit_episodes", s.pit_episodes, ValidRange::at_least(1));
  s.pit_way = params.count("pit_way", s.pit_way, ValidRange::at_least(2));
  s.pit_kept = params.count("pit_kept", s.pit_kept, ValidRange::at_least(1));
  s.pit_shot = params.count("pit_shot", s.pit_shot, ValidRange::at_least(1));
  s.pit_query = params.count("pit_query", s.pit_query, ValidRange::at_least(1));
  s.pit_alpha = params.real("pit_alpha", s.pit_alpha, ValidRange::above(0));

  s.epochs_new = params.count("epochs_new", s.epochs_new, ValidRange::at_least(0));
  s.lr_new = params.real("lr_new", s.lr_new, ValidRange::above(0));
  s.lamda_proto = params.real("lamda_proto", s.lamda_proto, ValidRange::between(0, 1));
  s.temperature = params.real("temperature", s.temperature, ValidRange::above(0));

  if (s.pit_way <= s.pit_kept || (s.pit_way - s.pit_kept) % 2 != 0) {
    throw MethodError(fmt::format("pit_way={} pit_kept={}: expected pit_way - pit_kept positive and even (the "
                                  "pseudo-novel classes are made in pairs)", s.pit_way, s.pit_kept));
  }
  return s;
}

}  // namespace fscil
