#include "metrics/convergence.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace fscil {

namespace {

StageConvergence judge(const std::string& stage, const std::vector<double>& accuracy) {
  StageConvergence judged;
  judged.stage = stage;
  judged.epochs = static_cast<int>(accuracy.size());
  judged.first = accuracy.front();
  judged.last = accuracy.back();
  if (judged.epochs < 2 * kConvergenceWindow) return judged;
  judged.window = kConvergenceWindow;
  const auto split = accuracy.end() - judged.window;
  judged.rise = *std::max_element(split, accuracy.end()) - *std::max_element(accuracy.begin(), split);
  judged.verdict = judged.rise >= kStillRisingPoints ? TrainingVerdict::still_rising : TrainingVerdict::converged;
  return judged;
}

}  // namespace

std::vector<StageConvergence> judge_stages(const std::vector<EpochLog>& log) {
  std::vector<std::string> stages;
  std::vector<std::vector<double>> accuracy;
  for (const EpochLog& row : log) {
    const auto scored = row.values.find(kBaseValidationKey);
    if (scored == row.values.end() || std::isnan(scored->second)) continue;
    const auto known = std::find(stages.begin(), stages.end(), row.stage);
    const auto index = static_cast<std::size_t>(known - stages.begin());
    if (known == stages.end()) {
      stages.push_back(row.stage);
      accuracy.emplace_back();
    }
    accuracy[index].push_back(scored->second);
  }
  std::vector<StageConvergence> judged;
  for (std::size_t s = 0; s < stages.size(); ++s) judged.push_back(judge(stages[s], accuracy[s]));
  return judged;
}

bool stage_has_levelled_off(const std::vector<EpochLog>& log, const std::string& stage) {
  for (const StageConvergence& judged : judge_stages(log)) {
    if (judged.stage == stage) {
      return judged.verdict == TrainingVerdict::converged && judged.rise > -kStillRisingPoints;
    }
  }
  return false;
}

TrainingVerdict run_verdict(const std::vector<StageConvergence>& stages) {
  if (stages.empty()) return TrainingVerdict::not_recorded;
  const auto any = [&](TrainingVerdict verdict) {
    return std::any_of(stages.begin(), stages.end(), [&](const StageConvergence& s) { return s.verdict == verdict; });
  };
  if (any(TrainingVerdict::still_rising)) return TrainingVerdict::still_rising;
  if (any(TrainingVerdict::unjudged)) return TrainingVerdict::unjudged;
  return TrainingVerdict::converged;
}

const char* verdict_name(TrainingVerdict verdict) {
  switch (verdict) {
    case TrainingVerdict::converged: return "converged";
    case TrainingVerdict::still_rising: return "still rising";
    case TrainingVerdict::unjudged: return "unjudged";
    case TrainingVerdict::not_recorded: return "not recorded";
  }
  return "not recorded";
}

std::string describe_stage(const StageConvergence& stage) {
  if (stage.verdict == TrainingVerdict::unjudged) {
    return fmt::format("{}: {} scored epochs, too few to judge ({:.1f}%)", stage.stage, stage.epochs, stage.last);
  }
  return fmt::format("{}: best of its last {} of {} epochs {:+.2f} points against the best before ({:.1f}% -> {:.1f}%)",
                     stage.stage, stage.window, stage.epochs, stage.rise, stage.first, stage.last);
}

}  // namespace fscil
