#include "methods/arp/arp_settings.h"

#include "core/named_choice.h"
#include "core/parameter_set.h"

namespace fscil {

ArpSettings ArpSettings::from(const ParameterSet& params) {
  ArpSettings s;
  s.base = SupervisedSchedule::from(params);
  s.way = static_cast<int>(params.integer("arp_way", s.way, ValidRange::at_least(1)));
  s.shot = static_cast<int>(params.integer("arp_shot", s.shot, ValidRange::at_least(1)));
  s.tasks = static_cast<int>(params.integer("arp_tasks", s.tasks, ValidRange::at_least(1)));
  s.relation_width = static_cast<int>(params.integer("arp_relation_width", s.relation_width, ValidRange::at_least(1)));
  s.early_stop_tol = static_cast<int>(params.integer("arp_early_stop_tol", s.early_stop_tol, ValidRange::at_least(0)));
  s.refined_test_rows =
      named_choice(params, "arp_test_rows", s.refined_test_rows, {{"plain", false}, {"refined", true}});
  return s;
}

}  // namespace fscil
