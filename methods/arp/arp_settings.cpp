#include "methods/arp/arp_settings.h"

#include "core/named_choice.h"
#include "core/parameter_set.h"

namespace fscil {

ArpSettings ArpSettings::from(const ParameterSet& params) {
  ArpSettings s;
  // The release's optimiser: plain SGD (its parsed momentum is never passed, main_SPPR_Nsynth.py
  // L60, L501), the rate falling by a cosine over every step (Utils.py L130-L137, called per
  // iteration at main L154-L155).
  SupervisedSchedule released;
  released.momentum = 0;
  released.nesterov = false;
  released.decay = LearningRateDecay::cosine;
  s.base = SupervisedSchedule::from(params, released);
  s.way = params.count("arp_way", s.way, ValidRange::at_least(1));
  s.shot = params.count("arp_shot", s.shot, ValidRange::at_least(1));
  s.tasks = params.count("arp_tasks", s.tasks, ValidRange::at_least(1));
  s.relation_width = params.count("arp_relation_width", s.relation_width, ValidRange::at_least(1));
  s.early_stop_tol = params.count("arp_early_stop_tol", s.early_stop_tol, ValidRange::at_least(0));
  s.refined_test_rows =
      named_choice(params, "arp_test_rows", s.refined_test_rows, {{"plain", false}, {"refined", true}});
  return s;
}

}  // namespace fscil
