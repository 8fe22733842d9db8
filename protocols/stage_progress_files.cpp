#include "protocols/stage_progress_files.h"

#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <cstdlib>

#include "core/error.h"
#include "core/number_text.h"
#include "core/shown_text.h"
#include "protocols/run_checkpoint.h"

namespace fscil {

namespace fs = std::filesystem;

StageProgressFiles::StageProgressFiles(fs::path folder, std::string identity, bool resuming, double interval_seconds,
                                       std::function<double()> elapsed, std::function<void(double)> resumed)
    : folder_(std::move(folder)),
      identity_(std::move(identity)),
      resuming_(resuming),
      interval_seconds_(interval_seconds),
      elapsed_(std::move(elapsed)),
      resumed_(std::move(resumed)) {}

fs::path StageProgressFiles::file_of(const std::string& stage) const {
  std::string name = stage;
  for (char& c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_') c = '_';
  }
  return folder_ / (name + ".ckpt");
}

std::optional<TrainedStage> StageProgressFiles::find(const std::string& stage) {
  const fs::path file = file_of(stage);
  if (!resuming_ || !fs::exists(file)) return std::nullopt;
  RunCheckpoint kept = load_checkpoint(file, identity_of(stage));
  resumed_(kept.elapsed_seconds);
  return stage_of_checkpoint(std::move(kept));
}

void StageProgressFiles::store(const std::string& stage, const TrainedStage& progress) {
  fs::create_directories(folder_);
  save_checkpoint(file_of(stage), checkpoint_of_stage(progress, identity_of(stage), elapsed_()));
  since_kept_ = Stopwatch();
}

void StageProgressFiles::clear(const fs::path& folder) {
  std::error_code ignored;
  fs::remove_all(folder, ignored);
}

fs::path stage_progress_folder(const fs::path& checkpoint_file) {
  return fs::path(checkpoint_file).replace_extension(".progress");
}

double stage_progress_interval() {
  const char* text = std::getenv("FSCIL_BENCH_KEEP_PROGRESS_SECONDS");
  if (text == nullptr || *text == '\0') return 600;
  const std::optional<double> seconds = parse_number<double>(text);
  if (!seconds || !std::isfinite(*seconds) || *seconds < 0) {
    throw ProtocolError(fmt::format("FSCIL_BENCH_KEEP_PROGRESS_SECONDS='{}': expected seconds between two keepings of "
                                    "a stage's progress, a number >= 0", shown_text(text)));
  }
  return *seconds;
}

}  // namespace fscil
