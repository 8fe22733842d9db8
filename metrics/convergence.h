#pragma once
#include <string>
#include <vector>

#include "metrics/session_outcome.h"

namespace fscil {

// Whether a training stage had finished learning when its schedule ended, judged from the
// base-validation accuracy it logged after each epoch (EpochLog::values["base_validation"]), by one
// rule for every method (docs/methods.md, "Did the training finish?"):
//   window = the last kConvergenceWindow epochs;
//   rise   = best accuracy in the window - best accuracy before it;
//   still rising when rise >= kStillRisingPoints, converged otherwise; unjudged below
//   2 x kConvergenceWindow scored epochs (a window's best against one epoch is noise).
// Best against best, so a noisy plateau does not read as rising and a late dip does not hide a
// rise; the window is the schedule's last few epochs, where a finished training gains nothing.
inline constexpr int kConvergenceWindow = 3;
inline constexpr double kStillRisingPoints = 1.0;
inline constexpr const char* kBaseValidationKey = "base_validation";
// Not learning: a stage whose mean training loss ("loss") never moved, every epoch within this
// fraction of its first, over two epochs or more. A working stage moves it by far more; a
// degenerate one (a temperature of 1e-45) keeps it at its chance value, ln C, to the digit.
inline constexpr double kFlatLossFraction = 1e-4;

enum class TrainingVerdict { converged, still_rising, unjudged, not_recorded, not_learning };

struct StageConvergence {
  std::string stage;
  int epochs = 0;  // epochs that logged a base-validation accuracy
  int window = 0;
  double first = 0, last = 0;  // accuracy after the first and the last epoch
  double best = 0;             // the best of any epoch
  double rise = 0;             // points; 0 when unjudged
  double loss = 0;             // the first epoch's loss, when the stage logged one
  TrainingVerdict verdict = TrainingVerdict::unjudged;
};

// Still rising or not learning: a stage the tables mark, and that never goes to the stage cache
// when it did not learn.
bool ended_unfinished(TrainingVerdict verdict);

// One entry per stage of `log` that scored base validation, in the order they trained; epochs
// whose accuracy is not a number (an empty split) are left out.
std::vector<StageConvergence> judge_stages(const std::vector<EpochLog>& log);
// The run's verdict from its stages: not learning if any stage is, else still rising if any stage
// is, converged if every stage was judged converged, unjudged when some could not be judged,
// not_recorded with no scored stage.
TrainingVerdict run_verdict(const std::vector<StageConvergence>& stages);
// True once `stage` of `log` has levelled off: judged converged (so it has scored at least
// 2 x kConvergenceWindow epochs) with its window's best within kStillRisingPoints of the best
// before, either way, and its last epoch within kStillRisingPoints of its best. Where
// `base_stop=converged` ends a stage, which keeps its last epoch: a window a point or more below
// the best before, or a last epoch a point or more below the best, is a dip of a noisy curve at a
// high learning rate, which a stop there would keep (simtex, seed 1: PITS-SC's pretraining stopped
// after 7 epochs at 75.1% where it had reached 78.2%).
bool stage_has_levelled_off(const std::vector<EpochLog>& log, const std::string& stage);
// "converged", "still rising", "unjudged", "not recorded", "not learning" (summary.csv's `training` column).
const char* verdict_name(TrainingVerdict verdict);
// "pretrain: best of its last 3 of 8 epochs +3.20 points against the best before (61.2% -> 88.4%)".
std::string describe_stage(const StageConvergence& stage);

}  // namespace fscil
