// The stage cache files a base under an identity naming everything that shaped it, gives it back
// exactly, and drops a damaged entry instead of using it.
#include "protocols/stage_cache.h"

#include <gtest/gtest.h>

#include <functional>

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
  outcomes[0].accuracy.all = 61.25;
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
  other.outcomes[0].accuracy.all = 10;
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

}  // namespace
}  // namespace fscil
