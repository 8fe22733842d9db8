#include "metrics/convergence.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace fscil {

namespace {

bool loss_never_moved(const std::vector<double>& loss) {
  if (loss.size() < 2 || !std::isfinite(loss.front())) return false;
  const double allowed = kFlatLossFraction * std::max(std::abs(loss.front()), 1e-12);
  return std::all_of(loss.begin(), loss.end(), [&](double value) { return std::abs(value - loss.front()) <= allowed; });
}

StageConvergence judge(const std::string& stage, const std::vector<double>& accuracy, const std::vector<double>& loss) {
  StageConvergence judged;
  judged.stage = stage;
  judged.epochs = static_cast<int>(accuracy.size());
  judged.first = accuracy.front();
  judged.last = accuracy.back();
  judged.best = *std::max_element(accuracy.begin(), accuracy.end());
  if (!loss.empty()) judged.loss = loss.front();
  if (loss_never_moved(loss)) {
    judged.verdict = TrainingVerdict::not_learning;
    return judged;
  }
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
  std::map<std::string, std::vector<double>> loss;
  for (const EpochLog& row : log) {
    if (const auto mean = row.values.find("loss"); mean != row.values.end()) loss[row.stage].push_back(mean->second);
  }
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
  for (std::size_t s = 0; s < stages.size(); ++s) judged.push_back(judge(stages[s], accuracy[s], loss[stages[s]]));
  return judged;
}

bool stage_has_levelled_off(const std::vector<EpochLog>& log, const std::string& stage) {
  for (const StageConvergence& judged : judge_stages(log)) {
    if (judged.stage == stage) {
      return judged.verdict == TrainingVerdict::converged && judged.rise > -kStillRisingPoints &&
             judged.best - judged.last < kStillRisingPoints;
    }
  }
  return false;
}

TrainingVerdict run_verdict(const std::vector<StageConvergence>& stages) {
  if (stages.empty()) return TrainingVerdict::not_recorded;
  const auto any = [&](TrainingVerdict verdict) {
    return std::any_of(stages.begin(), stages.end(), [&](const StageConvergence& s) { return s.verdict == verdict; });
  };
  if (any(TrainingVerdict::not_learning)) return TrainingVerdict::not_learning;
  if (any(TrainingVerdict::still_rising)) return TrainingVerdict::still_rising;
  if (any(TrainingVerdict::unjudged)) return TrainingVerdict::unjudged;
  return TrainingVerdict::converged;
}

bool ended_unfinished(TrainingVerdict verdict) {
  return verdict == TrainingVerdict::still_rising || verdict == TrainingVerdict::not_learning;
}

const char* verdict_name(TrainingVerdict verdict) {
  switch (verdict) {
    case TrainingVerdict::converged: return "converged";
    case TrainingVerdict::still_rising: return "still rising";
    case TrainingVerdict::unjudged: return "unjudged";
    case TrainingVerdict::not_recorded: return "not recorded";
    case TrainingVerdict::not_learning: return "not learning";
  }
  return "not recorded";
}

std::string describe_stage(const StageConvergence& stage) {
  if (stage.verdict == TrainingVerdict::not_learning) {
    return fmt::format("{}: its loss stayed at {:.4f} over all its epochs, not learning ({:.1f}% on base validation)",
                       stage.stage, stage.loss, stage.last);
  }
  if (stage.verdict == TrainingVerdict::unjudged) {
    return fmt::format("{}: {} scored epochs, too few to judge ({:.1f}%)", stage.stage, stage.epochs, stage.last);
  }
  return fmt::format("{}: best of its last {} of {} epochs {:+.2f} points against the best before ({:.1f}% -> {:.1f}%)",
                     stage.stage, stage.window, stage.epochs, stage.rise, stage.first, stage.last);
}

}  // namespace fscil
