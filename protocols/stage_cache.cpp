#include "protocols/stage_cache.h"

#include <fmt/format.h>

#include <chrono>
#include <thread>

#include "core/stable_hash.h"
#include "core/error.h"
#include "core/stop_request.h"

namespace fscil {

namespace {

// Segments with their protocol labels, as one text.
std::string segments_text(const SessionSchedule& schedule, const std::vector<std::int64_t>& segments) {
  std::string text;
  for (std::int64_t segment : segments) text += fmt::format("{}:{},", segment, schedule.label[segment]);
  return text;
}

}  // namespace

std::string base_stage_identity(const BaseStageInputs& inputs) {
  const SessionSchedule& schedule = *inputs.schedule;
  // Session 0 scores the base classes' part of the scored split.
  std::vector<std::int64_t> scored;
  for (std::int64_t segment : schedule.scored_segments(inputs.scored)) {
    if (schedule.label[segment] < schedule.plan.base_classes) scored.push_back(segment);
  }
  return fmt::format(
      "base stage: code={} method={} data={} run={} seed={} threads={} classes={}/{} train={} validation={} scored={}:{} "
      "parameters={}",
      inputs.code, inputs.method_base, inputs.dataset_key, stable_hash(inputs.run_values), inputs.seed, inputs.threads, schedule.plan.base_classes,
      schedule.plan.total_classes(), stable_hash(segments_text(schedule, schedule.train.front())),
      stable_hash(segments_text(schedule, schedule.validation)), to_string(inputs.scored),
      stable_hash(segments_text(schedule, scored)), stable_hash(inputs.method_parameters));
}

std::filesystem::path StageCache::file_of(const std::string& identity) const {
  return folder_ / fmt::format("base-{}.ckpt", stable_hash(identity));
}

std::filesystem::path StageCache::claim_file_of(const std::string& identity) const {
  std::filesystem::path folder = folder_;
  folder += "-claims";
  return folder / file_of(identity).filename().replace_extension(".lock");
}

std::optional<FileLock> StageCache::claim(const std::string& identity,
                                          const std::function<void(const std::string&)>& note) const {
  const std::filesystem::path lock_file = claim_file_of(identity);
  bool waited = false;
  try {
    std::error_code ignored;
    std::filesystem::create_directories(lock_file.parent_path(), ignored);
    while (true) {
      if (std::optional<FileLock> lock = FileLock::try_lock(lock_file, FileLock::Kind::exclusive)) return lock;
      if (!waited) note(fmt::format("waiting for {}, which another process is training (lock {}), to take it over",
                                    file_of(identity).filename().string(), lock_file.string()));
      waited = true;
      stop_if_requested();
      std::this_thread::sleep_for(std::chrono::milliseconds(250));
    }
  } catch (const FileError& error) {
    note(fmt::format("stage cache: cannot claim {}, so another process may train it too: {}",
                     file_of(identity).filename().string(), error.what()));
    return std::nullopt;
  }
}

std::optional<RunCheckpoint> StageCache::find(const std::string& identity, std::string& dropped) const {
  const std::filesystem::path file = file_of(identity);
  std::error_code missing;
  if (!std::filesystem::is_regular_file(file, missing)) return std::nullopt;
  try {
    RunCheckpoint checkpoint = load_checkpoint(file, identity);
    if (checkpoint.outcomes.size() == 1) return checkpoint;
    dropped = fmt::format("{}: holds {} sessions, expected the base session only", file.string(), checkpoint.outcomes.size());
  } catch (const ProtocolError& error) {
    dropped = error.what();
  }
  std::error_code ignored;
  std::filesystem::remove(file, ignored);
  return std::nullopt;
}

std::optional<RunCheckpoint> StageCache::find_or_claim(const std::string& identity, std::string& dropped,
                                                       const std::function<void(const std::string&)>& note,
                                                       std::optional<FileLock>& claim) const {
  if (std::optional<RunCheckpoint> found = find(identity, dropped)) return found;
  claim = this->claim(identity, note);
  return find(identity, dropped);
}

void StageCache::store(const std::string& identity, const RunCheckpoint& checkpoint) const {
  const std::filesystem::path file = file_of(identity);
  std::error_code ignored;
  if (std::filesystem::exists(file, ignored)) return;
  std::filesystem::create_directories(folder_);
  RunCheckpoint entry = checkpoint;
  entry.identity = identity;
  save_checkpoint(file, entry);
}

}  // namespace fscil
