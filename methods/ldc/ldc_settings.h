#pragma once
#include "methods/common/supervised_training.h"

namespace fscil {

class ParameterSet;

// LDC's hyper-parameters as named options. No runnable release exists (Bibikiller/LDC lacks
// base.py and sample(), docs/compared_methods.md "LDC") and the paper's text cannot be read here,
// so every value comes from the release's stored files where they give one (4548445c; train.py and
// train_and_test.sh at 49ece229), cited beside it; docs/methods.md, "ldc", marks the readings ours.
struct LdcSettings {
  SupervisedSchedule base;             // the shared pretraining schedule every method here gets
  double temperature = 16;             // cosine scale, base and sessions (train.py L30)
  int calibration_epochs = 500;        // ldc_calibration_epochs: passes of the PCU over the base classes (inc_trainer.py L137)
  double calibration_lr = 0.0003;      // ldc_calibration_lr: the release's 0.1 (inc_trainer.py L46-L53) diverges here (ours)
  int calibration_rounds = 3;          // ldc_calibration_rounds: the PCU's recurrent updates (helper.py L76-L79)
  int calibration_samples = 30;        // ldc_calibration_samples: drawn and real features per base class (helper.py L63, L107)
  double unit_rms = 1;                 // ldc_unit_rms: the base embeddings' root mean square where the PCU works (ours)
  int replay_samples = 5;              // ldc_replay_samples: kept per class for the sessions (Network.py L192, L216)
  int session_epochs = 150;            // ldc_session_epochs (epochs_new, train.py L20; Network.py L227)
  double session_lr = 0.01;            // ldc_session_lr: hard-coded in the release (Network.py L210)
  int session_batch = 50;              // ldc_session_batch: unshuffled (Network.py L230)

  static LdcSettings from(const ParameterSet& params);
};

}  // namespace fscil
