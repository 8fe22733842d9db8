#pragma once
#include <string>
#include <vector>

#include "metrics/session_outcome.h"

namespace fscil {

// Whether a training stage had finished learning when its schedule ended, judged from the
// base-validation accuracy it logged after each epoch (EpochLog::values["base_validation"]), by one
// rule for every method (docs/methods.md, "Did the training finish?"):
//   window = min(kConvergenceWindow, scored epochs / 2) last epochs;
//   rise   = best accuracy in the window - best accuracy before it;
//   still rising when rise >= kStillRisingPoints, converged otherwise; unjudged below 2 epochs.
// Best against best, so a noisy plateau does not read as rising and a late dip does not hide a
// rise; the window is the schedule's last few epochs, where a finished training gains nothing.
inline constexpr int kConvergenceWindow = 3;
inline constexpr double kStillRisingPoints = 1.0;
inline constexpr const char* kBaseValidationKey = "base_validation";

enum class TrainingVerdict { converged, still_rising, unjudged, not_recorded };

struct StageConvergence {
  std::string stage;
  int epochs = 0;  // epochs that logged a base-validation accuracy
  int window = 0;
  double first = 0, last = 0;  // accuracy after the first and the last epoch
  double rise = 0;             // points; 0 when unjudged
  TrainingVerdict verdict = TrainingVerdict::unjudged;
};

// One entry per stage of `log` that scored base validation, in the order they trained.
std::vector<StageConvergence> judge_stages(const std::vector<EpochLog>& log);
// The run's verdict from its stages: still rising if any stage is, converged if every stage was
// judged converged, unjudged when some could not be judged, not_recorded with no scored stage.
TrainingVerdict run_verdict(const std::vector<StageConvergence>& stages);
// True once `stage` of `log` has scored at least 2 x kConvergenceWindow epochs (a full window and
// as many before it) and is judged converged: where `base_stop=converged` ends a stage.
bool stage_has_converged(const std::vector<EpochLog>& log, const std::string& stage);
// "converged", "still rising", "unjudged", "not recorded" (summary.csv's `training` column).
const char* verdict_name(TrainingVerdict verdict);
// "pretrain: +3.20 points in its last 3 of 8 epochs (61.2% -> 88.4%)".
std::string describe_stage(const StageConvergence& stage);

}  // namespace fscil
