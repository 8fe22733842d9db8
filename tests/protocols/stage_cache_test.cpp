// The stage cache files a base under an identity naming everything that shaped it, gives it back
// exactly, and drops a damaged entry instead of using it; a run that needs an entry another is
// training waits for it and takes it over.
#include "protocols/stage_cache.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <functional>
#include <fstream>
#include <future>
#include <sstream>
#include <thread>

#include "core/progress_reporter.h"
#include "protocols/shared_stages.h"

#include "tests/temporary_directory.h"

namespace fscil {
namespace {

namespace fs = std::filesystem;

// 2 base classes and 1 novel class; segments 0-3 train the base, 4-5 its validation, 6-8 test
// (8 is the novel class's), 9 is the novel class's shot.
SessionSchedule small_schedule() {
  SessionSchedule schedule;
  schedule.plan.base_classes = 2;
  schedule.plan.way = 1;
  schedule.plan.shot = 1;
  schedule.plan.sessions = 2;
  schedule.train = {{0, 1, 2, 3}, {9}};
  schedule.validation = {4, 5};
  schedule.test = {6, 7, 8};
  schedule.scored_validation = {4, 5};
  schedule.label = {0, 0, 1, 1, 0, 1, 0, 1, 2, 2};
  return schedule;
}

struct Inputs {
  SessionSchedule schedule = small_schedule();
  BaseStageInputs base{"code", "pits-sc", "data", {{"front_end", "sr=1000 n_fft=128"}, {"recompute", "none"}}, 1, 2,
                       EvaluationSplit::test, {{"pretrain_lr", "0.1"}, {"cutmix_alpha", "0.8"}}, nullptr};
  std::string identity() {
    base.schedule = &schedule;
    return base_stage_identity(base);
  }
};

TEST(StageCache, TheIdentityChangesWithEverythingTheBaseSessionSeesAndNothingElse) {
  const std::string reference = Inputs().identity();
  const std::vector<std::pair<std::string, std::function<void(Inputs&)>>> shaping = {
      {"code", [](Inputs& in) { in.base.code = "other"; }},
      {"method", [](Inputs& in) { in.base.method_base = "cop-fscil:no-pcqa"; }},
      {"dataset", [](Inputs& in) { in.base.dataset_key = "other"; }},
      {"the front end", [](Inputs& in) { in.base.run_values["front_end"] = "sr=1000 n_fft=256"; }},
      {"recomputation", [](Inputs& in) { in.base.run_values["recompute"] = "stages"; }},
      {"seed", [](Inputs& in) { in.base.seed = 2; }},
      {"threads", [](Inputs& in) { in.base.threads = 1; }},
      {"scored split", [](Inputs& in) { in.base.scored = EvaluationSplit::validation; }},
      {"a parameter's value", [](Inputs& in) { in.base.method_parameters["pretrain_lr"] = "0.05"; }},
      {"one more parameter", [](Inputs& in) { in.base.method_parameters["pspc_probes"] = "100"; }},
      {"a base training segment", [](Inputs& in) { in.schedule.train[0][3] = 9; }},
      {"a validation segment", [](Inputs& in) { in.schedule.validation = {4}; }},
      {"a base class's test segment", [](Inputs& in) { in.schedule.test = {6, 8}; }},
      {"a label", [](Inputs& in) { in.schedule.label[1] = 1; }},
      {"the classes to come", [](Inputs& in) { in.schedule.plan.sessions = 3; }},
  };
  for (const auto& [what, change] : shaping) {
    Inputs changed;
    change(changed);
    EXPECT_NE(changed.identity(), reference) << what;
  }
  const std::vector<std::pair<std::string, std::function<void(Inputs&)>>> unseen = {
      {"a novel class's shot", [](Inputs& in) { in.schedule.train[1] = {8}; }},
      {"a novel class's test segment", [](Inputs& in) { in.schedule.test = {6, 7}; }},
      {"shots per class", [](Inputs& in) { in.schedule.plan.shot = 3; }},
  };
  for (const auto& [what, change] : unseen) {
    Inputs changed;
    change(changed);
    EXPECT_EQ(changed.identity(), reference) << what;
  }
}

RunCheckpoint base_checkpoint(int sessions) {
  std::vector<SessionOutcome> outcomes(static_cast<std::size_t>(sessions));
  outcomes[0].accuracy.all = outcomes[0].accuracy.base = outcomes[0].accuracy.current = 61.25;  // the base classes alone
  outcomes[0].train_seconds = 42;
  return {"run identity", outcomes, 50, {{"encoder.w", torch::arange(6.0).view({2, 3})}}, std::mt19937_64(7),
          torch::arange(5, torch::kUInt8)};
}

TEST(StageCache, GivesBackWhatItStoredAndNeverOverwritesAnEntry) {
  TemporaryDirectory folder;
  const StageCache cache(folder.path() / "stages");
  std::string dropped;
  EXPECT_FALSE(cache.find("base A", dropped).has_value());
  EXPECT_TRUE(dropped.empty());

  cache.store("base A", base_checkpoint(1));
  std::optional<RunCheckpoint> found = cache.find("base A", dropped);
  ASSERT_TRUE(found.has_value()) << dropped;
  EXPECT_EQ(found->identity, "base A");
  ASSERT_EQ(found->outcomes.size(), 1u);
  EXPECT_EQ(found->outcomes[0].accuracy.all, 61.25);
  EXPECT_EQ(found->outcomes[0].train_seconds, 42);
  EXPECT_TRUE(torch::equal(found->method_state.at("encoder.w"), torch::arange(6.0).view({2, 3})));
  EXPECT_EQ(found->generator, std::mt19937_64(7));
  EXPECT_TRUE(torch::equal(found->torch_random_state, torch::arange(5, torch::kUInt8)));
  EXPECT_FALSE(cache.find("base B", dropped).has_value());

  RunCheckpoint other = base_checkpoint(1);
  other.outcomes[0].accuracy.all = other.outcomes[0].accuracy.base = other.outcomes[0].accuracy.current = 10;
  cache.store("base A", other);
  EXPECT_EQ(cache.find("base A", dropped)->outcomes[0].accuracy.all, 61.25);
}

TEST(StageCache, ADamagedOrForeignEntryIsDroppedWithTheReason) {
  TemporaryDirectory folder;
  const StageCache cache(folder.path());
  cache.store("base A", base_checkpoint(1));
  const fs::path file = cache.file_of("base A");
  fs::resize_file(file, fs::file_size(file) - 10);
  std::string dropped;
  EXPECT_FALSE(cache.find("base A", dropped).has_value());
  EXPECT_NE(dropped.find(file.string()), std::string::npos) << dropped;
  EXPECT_NE(dropped.find("corrupt"), std::string::npos) << dropped;
  EXPECT_FALSE(fs::exists(file));

  // A checkpoint of a whole run where a base belongs: never taken for a base.
  RunCheckpoint whole = base_checkpoint(3);
  whole.identity = "base A";
  save_checkpoint(file, whole);
  dropped.clear();
  EXPECT_FALSE(cache.find("base A", dropped).has_value());
  EXPECT_NE(dropped.find("holds 3 sessions"), std::string::npos) << dropped;
}

TEST(StageCache, AClaimIsWaitedForUntilItsHolderLetsGo) {
  TemporaryDirectory folder;
  const StageCache cache(folder.path() / "stages");
  const auto no_note = [](const std::string& line) { ADD_FAILURE() << "unexpected note: " << line; };
  std::optional<FileLock> first = cache.claim("base A", no_note);
  ASSERT_TRUE(first.has_value());
  EXPECT_TRUE(cache.claim("base B", no_note).has_value());  // another entry: no wait
  EXPECT_TRUE(fs::exists(folder.path() / "stages-claims" / cache.file_of("base A").filename().replace_extension(".lock")));

  std::atomic<int> waits{0};
  auto second = std::async(std::launch::async, [&] {
    return cache.claim("base A", [&](const std::string& line) {
      EXPECT_NE(line.find("which another process is training"), std::string::npos) << line;
      ++waits;
    }).has_value();
  });
  EXPECT_EQ(second.wait_for(std::chrono::milliseconds(600)), std::future_status::timeout);
  EXPECT_EQ(waits.load(), 1);
  first.reset();
  EXPECT_TRUE(second.get());
  EXPECT_EQ(waits.load(), 1);  // told once, however long it waited
}

TEST(StageCache, AClaimThatCannotBeMadeSaysWhyAndTheRunTrainsUnclaimed) {
  TemporaryDirectory folder;
  std::ofstream(folder.path() / "stages-claims") << "a file where the claims' folder belongs\n";
  const StageCache cache(folder.path() / "stages");
  std::string said;
  EXPECT_FALSE(cache.claim("base A", [&](const std::string& line) { said += line; }).has_value());
  EXPECT_NE(said.find("cannot claim"), std::string::npos) << said;
  EXPECT_NE(said.find("stages-claims"), std::string::npos) << said;
}

TrainedStage stage_trained_in(double seconds) {
  return {{{"encoder.w", torch::full({2}, seconds)}}, std::mt19937_64(3), torch::arange(5, torch::kUInt8), {}, {},
          seconds};
}

// Two SharedStages on one cache folder stand for two processes (run-cells' cells): flock()s
// conflict between open files, in one process as between two.
TEST(SharedStages, ARunWaitsForAStageAnotherIsTrainingAndTakesItOver) {
  TemporaryDirectory folder;
  SharedStages trainer{StageCache(folder.path() / "stages")}, waiter{StageCache(folder.path() / "stages")};
  ASSERT_FALSE(trainer.find("pretraining", nullptr).has_value());  // found nowhere: the trainer claims it

  std::ostringstream notes;
  ProgressReporter progress(&notes);
  auto taken = std::async(std::launch::async, [&] { return waiter.find("pretraining", &progress); });
  EXPECT_EQ(taken.wait_for(std::chrono::milliseconds(600)), std::future_status::timeout);
  trainer.store("pretraining", stage_trained_in(12.5), "pits-sc", nullptr);
  const std::optional<SharedStages::Found> found = taken.get();
  ASSERT_TRUE(found.has_value());
  EXPECT_EQ(found->source, "from the stage cache");
  EXPECT_EQ(found->stage.seconds, 12.5);
  EXPECT_TRUE(torch::equal(found->stage.state.at("encoder.w"), torch::full({2}, 12.5)));
  EXPECT_NE(notes.str().find("which another process is training"), std::string::npos) << notes.str();
}

TEST(SharedStages, AStageGivenUpUnfiledIsTrainedByTheRunThatWaited) {
  TemporaryDirectory folder;
  SharedStages trainer{StageCache(folder.path() / "stages")}, waiter{StageCache(folder.path() / "stages")};
  ASSERT_FALSE(trainer.find("pretraining", nullptr).has_value());
  auto taken = std::async(std::launch::async, [&] { return waiter.find("pretraining", nullptr).has_value(); });
  EXPECT_EQ(taken.wait_for(std::chrono::milliseconds(600)), std::future_status::timeout);
  trainer.release("pretraining");  // the trainer's run failed, or its stage did not learn
  EXPECT_FALSE(taken.get());       // nothing filed: the waiter trains it, and now holds the claim
  SharedStages third_run{StageCache(folder.path() / "stages")};
  auto third = std::async(std::launch::async, [&] { return third_run.find("pretraining", nullptr).has_value(); });
  EXPECT_EQ(third.wait_for(std::chrono::milliseconds(600)), std::future_status::timeout);
  waiter.store("pretraining", stage_trained_in(3), "cop-fscil/cpi", nullptr);
  EXPECT_TRUE(third.get());
}

}  // namespace
}  // namespace fscil
