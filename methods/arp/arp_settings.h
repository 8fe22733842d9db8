#pragma once
#include "methods/common/supervised_training.h"

namespace fscil {

class ParameterSet;

// ARP's hyper-parameters as named options. Defaults are the release's NS-100 run
// (chester-w-xie/APR main_SPPR_Nsynth.py and README.md at 78426ecf); docs/methods.md gives each
// line. The base schedule is the shared pretraining schedule every method here gets.
struct ArpSettings {
  SupervisedSchedule base;  // the shared pretraining schedule
  int way = 5;              // arp_way: classes a task replaces by their supports' means (--way, L453)
  int shot = 5;             // arp_shot: supports per episode class (--shot, L454)
  int tasks = 3;            // arp_tasks: tasks per step; the episode has way + tasks classes (--batch_task, L466)
  int relation_width = 64;  // arp_relation_width: the relation head's first layer (--embedding, L467)
  int early_stop_tol = 50;  // arp_early_stop_tol: epochs without a lower validation loss before stopping (README L18)

  static ArpSettings from(const ParameterSet& params);
};

}  // namespace fscil
