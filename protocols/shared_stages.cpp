#include "protocols/shared_stages.h"

#include <fmt/format.h>

#include "core/progress_reporter.h"
#include "metrics/convergence.h"

namespace fscil {

std::optional<SharedStages::Found> SharedStages::find(const std::string& identity, ProgressReporter* progress) {
  if (const auto kept = kept_.find(identity); kept != kept_.end()) {
    return Found{kept->second.first, "shared with " + kept->second.second};
  }
  if (!cache_) return std::nullopt;
  std::string dropped;
  std::optional<FileLock> claim;
  const auto note = [&](const std::string& line) {
    if (progress != nullptr) progress->note(line);
  };
  std::optional<RunCheckpoint> cached = claimed(identity)  // a run of this process trains it now
                                            ? cache_->find(identity, dropped)
                                            : cache_->find_or_claim(identity, dropped, note, claim);
  if (!dropped.empty()) note(fmt::format("stage cache entry dropped, the stage is trained again: {}", dropped));
  if (claim && !cached) claims_.emplace(identity, std::move(*claim));
  if (!cached) return std::nullopt;
  return Found{stage_of_checkpoint(std::move(*cached)), "from the stage cache"};
}

void SharedStages::store(const std::string& identity, TrainedStage stage, const std::string& trained_by,
                         ProgressReporter* progress) {
  if (cache_) {
    try {
      cache_->store(identity, checkpoint_of_stage(stage, {}, stage.seconds));
    } catch (const std::exception& error) {
      if (progress != nullptr) progress->note(fmt::format("stage cache not written: {}", error.what()));
    }
  }
  release(identity);
  kept_.emplace(identity, std::make_pair(std::move(stage), trained_by));
}

std::optional<TrainedStage> RunStages::find(const std::string& stage) {
  const std::string identity = identity_of_(stage);
  std::optional<SharedStages::Found> found = shared_.find(identity, progress_);
  if (!found) {
    if (shared_.claimed(identity)) claimed_.push_back(identity);
    return std::nullopt;
  }
  taken_ = stage + " " + found->source;
  if (progress_ != nullptr) {
    progress_->note(fmt::format("{}, trained in {:.1f} s", taken_, found->stage.seconds));
  }
  return std::move(found->stage);
}

void RunStages::store(const std::string& stage, TrainedStage trained) {
  // Filed at once, so that a run waiting for it (another cell) goes on while this one trains what
  // follows it; a stage that learned nothing is this run's result to report, never a base for others.
  const std::string identity = identity_of_(stage);
  for (const StageConvergence& judged : judge_stages(trained.training_log)) {
    if (judged.verdict != TrainingVerdict::not_learning) continue;
    if (progress_ != nullptr) progress_->note(fmt::format("stages not shared or cached: {}", describe_stage(judged)));
    shared_.release(identity);
    return;
  }
  shared_.store(identity, std::move(trained), method_name_, progress_);
}

RunStages::~RunStages() {
  for (const std::string& identity : claimed_) shared_.release(identity);  // those it stored are released already
}

}  // namespace fscil
