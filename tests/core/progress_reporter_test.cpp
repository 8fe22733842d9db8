#include "core/progress_reporter.h"

#include <gtest/gtest.h>

#include <sstream>
#include <thread>

namespace fscil {
namespace {

std::size_t occurrences(const std::string& text, const std::string& part) {
  std::size_t count = 0;
  for (auto at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++count;
  return count;
}

// Issue 70: a session of `reproduce nps` at N_ps = 1000 printed nothing for 27 s.
TEST(ProgressReporter, AHeartbeatSpeaksOnlyAfterItsSilence) {
  std::ostringstream out;
  ProgressReporter progress(&out);
  {
    const Heartbeat heartbeat(progress, std::chrono::seconds(2));
    progress.stage("cop-fscil on simtex, seed 1 (1 of 1 runs)");
    std::this_thread::sleep_for(std::chrono::milliseconds(1200));
    progress.note("session 0 accuracy 80.00%");  // said within its silence: no heartbeat yet
    std::this_thread::sleep_for(std::chrono::milliseconds(1200));
    EXPECT_EQ(occurrences(out.str(), "still working"), 0u) << out.str();
    std::this_thread::sleep_for(std::chrono::milliseconds(1800));
  }
  const std::string said = out.str();
  EXPECT_EQ(occurrences(said, "[fscil-bench]   still working (cop-fscil on simtex, seed 1 (1 of 1 runs)), "), 1u) << said;
  const std::string after = said.substr(said.find("session 0"));
  EXPECT_NE(after.find("still working"), std::string::npos) << "after the note, not before";
}

// The sf-instruments lane printed "pseudo-incremental epoch 1/40 ... elapsed 1325s ETA 51661s":
// the pretraining before it counted as that phase's first epoch.
TEST(ProgressReporter, APhasesTimeToGoCountsFromTheEndOfThePhaseBefore) {
  std::ostringstream out;
  ProgressReporter progress(&out);
  progress.stage("pits-sc on simtex, seed 1");
  std::this_thread::sleep_for(std::chrono::milliseconds(1600));
  progress.epoch("pretrain", 1, 1, 1.5);
  progress.epoch("pseudo-incremental", 1, 40, 0.5);
  const std::string said = out.str();
  EXPECT_NE(said.find("pretrain epoch 1/1 loss 1.5000 elapsed "), std::string::npos) << said;
  EXPECT_EQ(said.find("pretrain epoch 1/1 loss 1.5000 elapsed 0s"), std::string::npos) << said;
  EXPECT_NE(said.find("pseudo-incremental epoch 1/40 loss 0.5000 elapsed 0s ETA 0s"), std::string::npos) << said;
}

}  // namespace
}  // namespace fscil
