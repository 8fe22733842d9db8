#pragma once
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include "core/stopwatch.h"
#include "methods/method.h"

namespace fscil {

// One run's StageProgressStore: each stage's progress is a checkpoint file in `folder`
// (OUT/checkpoints/RUN.progress/STAGE.ckpt, protocols/run_checkpoint.h: a truncated, altered or
// foreign file is refused with one line), kept every `interval_seconds` and when a stage ends,
// read back only when the run resumes (`resuming`). `elapsed` gives the run's seconds so far, which
// a file keeps; `resumed` receives them when the run continues from it, so that its total time
// counts the earlier process's work.
class StageProgressFiles : public StageProgressStore {
 public:
  StageProgressFiles(std::filesystem::path folder, std::string identity, bool resuming, double interval_seconds,
                     std::function<double()> elapsed, std::function<void(double)> resumed);
  std::optional<TrainedStage> find(const std::string& stage) override;
  bool due() const override { return since_kept_.seconds() >= interval_seconds_; }
  void store(const std::string& stage, const TrainedStage& progress) override;
  std::string origin(const std::string& stage) const override { return file_of(stage).string(); }
  // Removes every stage's progress: once the base session's checkpoint is written it holds it all.
  void clear() const { clear(folder_); }
  static void clear(const std::filesystem::path& folder);

 private:
  std::filesystem::path file_of(const std::string& stage) const;
  std::string identity_of(const std::string& stage) const { return identity_ + " stage_in_progress=" + stage; }

  std::filesystem::path folder_;
  std::string identity_;
  bool resuming_;
  double interval_seconds_;
  std::function<double()> elapsed_;
  std::function<void(double)> resumed_;
  Stopwatch since_kept_;
};

// The folder of the run whose checkpoint is `checkpoint_file`.
std::filesystem::path stage_progress_folder(const std::filesystem::path& checkpoint_file);

// Seconds between two keepings of a stage's progress: FSCIL_BENCH_KEEP_PROGRESS_SECONDS (a number
// >= 0; 0 keeps every epoch), 600 when unset. ProtocolError for any other value.
double stage_progress_interval();

}  // namespace fscil
