#pragma once
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "methods/method.h"
#include "protocols/stage_cache.h"

namespace fscil {

class ProgressReporter;

// Stages that several methods' base sessions train alike (MethodEntry::shared_stages), kept for
// the runs of one command and, with the stage cache, for later commands: the first run to train
// one files it under its identity, and a run of another method with that identity takes it over.
class SharedStages {
 public:
  // Without a cache, stages are shared within the command only.
  explicit SharedStages(std::optional<StageCache> cache = std::nullopt) : cache_(std::move(cache)) {}

  struct Found {
    TrainedStage stage;
    std::string source;  // "shared with <method>" or "from the stage cache"
  };
  // The stage filed under `identity`, if any; a damaged cache entry is removed and noted. When the
  // cache has none, the caller is to train it: the entry is claimed (StageCache::claim) until
  // store() or release(), and a stage another process is training is waited for and taken.
  std::optional<Found> find(const std::string& identity, ProgressReporter* progress);
  // Keeps `stage` for this command and files it in the cache (once; a cache that cannot be
  // written is noted, as it costs time, not the run).
  void store(const std::string& identity, TrainedStage stage, const std::string& trained_by,
             ProgressReporter* progress);
  // Gives up the claim on `identity` without filing a stage (the run failed, or the stage did
  // not learn): a waiting process trains it itself.
  void release(const std::string& identity) { claims_.erase(identity); }
  // Whether this process holds the claim on `identity` (find() took it).
  bool claimed(const std::string& identity) const { return claims_.count(identity) > 0; }

 private:
  std::map<std::string, std::pair<TrainedStage, std::string>> kept_;
  std::optional<StageCache> cache_;
  std::map<std::string, FileLock> claims_;  // entries this process is training
};

// One run's StageStore: it names each stage's identity from the run's values (IdentityOf),
// remembers which stage it took over, and from where, for the run's record, and files each stage
// it trains as soon as the method stores it, unless the stage did not learn. A stage stays valid
// whatever the run does after it (the same inputs give the same stage), so a run that fails later
// in its base session still shares it; it gives up the claims of stages it never stored.
class RunStages : public StageStore {
 public:
  using IdentityOf = std::function<std::string(const std::string& stage)>;
  RunStages(SharedStages& shared, IdentityOf identity_of, std::string method_name, ProgressReporter* progress)
      : shared_(shared), identity_of_(std::move(identity_of)), method_name_(std::move(method_name)), progress_(progress) {}
  ~RunStages();
  RunStages(const RunStages&) = delete;
  RunStages& operator=(const RunStages&) = delete;
  std::optional<TrainedStage> find(const std::string& stage) override;
  void store(const std::string& stage, TrainedStage trained) override;
  // "<stage> shared with <method>" or "<stage> from the stage cache"; empty when it trained every stage.
  const std::string& taken() const { return taken_; }

 private:
  SharedStages& shared_;
  IdentityOf identity_of_;
  std::string method_name_;
  ProgressReporter* progress_;
  std::string taken_;
  std::vector<std::string> claimed_;  // identities it found nowhere and claimed, to train them
};

}  // namespace fscil
