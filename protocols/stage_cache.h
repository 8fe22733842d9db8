#pragma once
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>

#include "core/file_lock.h"
#include "protocols/run_checkpoint.h"
#include "protocols/session_schedule.h"

namespace fscil {

// Everything that shapes a trained base session and its session-0 score.
struct BaseStageInputs {
  std::string code;         // the executable's digest: any change to the code is another base
  std::string method_base;  // Method::shared_base_key(), or the method's name when it shares none
  std::string dataset_key;  // the prepared segments (PreparedDataset::cache_key)
  // Everything else the data and the run read: the front end (cache_key covers segments only),
  // dataset knobs, and run-wide values such as recompute (same numbers, not the same peak memory).
  std::map<std::string, std::string> run_values;
  std::uint64_t seed = 0;
  int threads = 0;
  EvaluationSplit scored = EvaluationSplit::test;
  std::map<std::string, std::string> method_parameters;  // every value the method read
  const SessionSchedule* schedule = nullptr;             // its base session, validation and session-0 scoring
};

// One line naming those inputs: the identity a cached base is filed and checked under.
std::string base_stage_identity(const BaseStageInputs& inputs);

// Base sessions trained once and reused (`--no-stage-cache` turns it off): the run checkpoint
// after session 0 (protocols/run_checkpoint.h), filed in FOLDER under a digest of its identity.
// A run, variant, sweep cell or Slurm task whose base has the same identity continues from it
// as `--resume` continues from a run's own checkpoint, so its numbers are those of a run that
// trained its base itself. A run in another process that needs an entry being trained (run-cells,
// two commands on one cache) waits for it through claim() rather than training it too.
class StageCache {
 public:
  explicit StageCache(std::filesystem::path folder) : folder_(std::move(folder)) {}

  // The cached base of `identity`, if there is one. An entry that cannot be read is removed
  // (the base is trained again) and `dropped` says why.
  std::optional<RunCheckpoint> find(const std::string& identity, std::string& dropped) const;
  // Files `checkpoint` (whole, or not at all) unless an entry for `identity` exists.
  void store(const std::string& identity, const RunCheckpoint& checkpoint) const;
  std::filesystem::path file_of(const std::string& identity) const;
  // The claim of the run that will train `identity`'s entry: a FileLock on claim_file_of(identity),
  // held until the entry is filed (or the run ends). While another process holds it, waits (a
  // stop request ends the wait: StopRequested) and says so once through `note`. Where no lock
  // file can be made, `note` says why and it returns nullopt: that run trains unclaimed, as the
  // cache is an economy, not a result.
  std::optional<FileLock> claim(const std::string& identity, const std::function<void(const std::string&)>& note) const;
  // find(), and where it finds nothing, claim() into `claim` and find() again: another process
  // may have filed the entry while this one waited for its claim.
  std::optional<RunCheckpoint> find_or_claim(const std::string& identity, std::string& dropped,
                                             const std::function<void(const std::string&)>& note,
                                             std::optional<FileLock>& claim) const;
  // FOLDER-claims/<entry>.lock, so that FOLDER holds entries only. Lock files are never removed
  // (removing one under a waiting process would let two claims hold at once).
  std::filesystem::path claim_file_of(const std::string& identity) const;

 private:
  std::filesystem::path folder_;
};

}  // namespace fscil
