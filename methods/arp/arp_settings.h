#pragma once
#include "methods/common/supervised_training.h"

namespace fscil {

class ParameterSet;

// ARP's hyper-parameters as named options. Defaults are the release's NS-100 run
// (chester-w-xie/APR main_SPPR_Nsynth.py and README.md at 78426ecf); docs/methods.md gives each
// line. The base schedule reads the shared pretraining keys, defaulting to the release's plain SGD
// with a per-step cosine.
struct ArpSettings {
  SupervisedSchedule base;  // the shared pretraining keys, with the release's optimiser as defaults
  int way = 5;              // arp_way: classes a task replaces by their supports' means (--way, L453)
  int shot = 5;             // arp_shot: supports per episode class (--shot, L454)
  int tasks = 3;            // arp_tasks: tasks per step; the episode has way + tasks classes (--batch_task, L466)
  int relation_width = 64;  // arp_relation_width: the relation head's first layer (--embedding, L467)
  int early_stop_tol = 50;  // arp_early_stop_tol: epochs without a lower validation loss before stopping (README L18)
  // arp_test_rows: what the relation head scores at test (ours to offer; the release's is plain).
  // plain: the rows as they are (forward_test, FSCIL_model_define_V1.py L162-L165); refined: every
  // seen row refined by the attention first, the novel rows standing in as a task's replaced rows
  // do in training (their keys zero), which is what the paper's abstract describes.
  bool refined_test_rows = false;

  static ArpSettings from(const ParameterSet& params);
};

}  // namespace fscil
