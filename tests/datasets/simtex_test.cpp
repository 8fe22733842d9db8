#include "datasets/simtex.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "datasets/segmenter.h"

namespace fscil {
namespace {

TEST(Simtex, SameSeedGivesByteIdenticalRecordingsWhateverTheThreadCount) {
  const SimtexConfig config = simtex_mini_config();
  const auto one = generate_simtex(config, 1);
  const auto two = generate_simtex(config, 2);
  ASSERT_EQ(one.size(), two.size());
  for (std::size_t r = 0; r < one.size(); ++r) {
    ASSERT_EQ(one[r].signal.size(), two[r].signal.size());
    ASSERT_EQ(0, std::memcmp(one[r].signal.data(), two[r].signal.data(), one[r].signal.size() * sizeof(float)));
    ASSERT_EQ(one[r].context, two[r].context);
  }
}

TEST(Simtex, DifferentSeedsGiveDifferentData) {
  SimtexConfig config = simtex_mini_config();
  const auto first = generate_simtex(config);
  config.seed = 2;
  const auto second = generate_simtex(config);
  EXPECT_NE(first[0].signal, second[0].signal);
}

TEST(Simtex, ShapesFollowTheRealDatasets) {
  const SimtexConfig haptex = simtex_haptex_config();
  EXPECT_EQ(haptex.classes, 120);
  EXPECT_EQ(haptex.channels(), 5);
  EXPECT_EQ(haptex.sample_rate, 1000);
  // 10 recordings of 5 s cut into 0.5 s segments: 100 per class.
  EXPECT_EQ(haptex.recordings_per_class * static_cast<int>(haptex.recording_seconds / 0.5), 100);
  const SimtexConfig lmt = simtex_lmt_config();
  EXPECT_EQ(lmt.classes, 108);
  EXPECT_EQ(lmt.channels(), 3);
  EXPECT_EQ(lmt.recordings_per_class * static_cast<int>(lmt.recording_seconds / 0.8 + 1e-9), 120);

  const auto recordings = generate_simtex(simtex_mini_config());
  ASSERT_EQ(recordings.size(), 20u * 6u);
  const SegmentSet set = segment_recordings(recordings, {500, 500, 0});
  EXPECT_EQ(set.count(), 20 * 6 * 5);
  for (float value : set.signals.values) ASSERT_TRUE(std::isfinite(value));
  EXPECT_EQ(recordings[7].class_index, 1);
  EXPECT_EQ(recordings.back().group_index, 3);
}

TEST(Simtex, ZeroContextStrengthSharesOneContextPerClass) {
  SimtexConfig config = simtex_mini_config();
  config.context_strength = 0.0;
  const auto recordings = generate_simtex(config);
  for (const auto& recording : recordings) {
    const auto& first_of_class = recordings[recording.class_index * config.recordings_per_class];
    EXPECT_EQ(recording.context, first_of_class.context);
  }
  config.context_strength = 1.0;
  const auto spread = generate_simtex(config);
  EXPECT_NE(spread[0].context.at("scan_speed"), spread[1].context.at("scan_speed"));
}

}  // namespace
}  // namespace fscil
