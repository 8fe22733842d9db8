#include "datasets/segmenter.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"

namespace fscil {
namespace {

Recording ramp_recording(const std::string& id, int class_index, std::int64_t channels, std::int64_t length) {
  Recording recording;
  recording.id = id;
  recording.class_index = class_index;
  recording.group_index = class_index / 2;
  recording.channels = channels;
  recording.length = length;
  for (std::int64_t c = 0; c < channels; ++c) {
    for (std::int64_t n = 0; n < length; ++n) recording.signal.push_back(static_cast<float>(1000 * c + n));
  }
  recording.context = {{"scan_speed", 10.0 + class_index}};
  return recording;
}

TEST(Segmenter, CutsEveryRecordingIntoHopSpacedSegments) {
  const std::vector<Recording> recordings = {ramp_recording("a", 0, 2, 100), ramp_recording("b", 3, 2, 70)};
  const SegmentSet set = segment_recordings(recordings, {30, 20, 0});
  // (100 - 30) / 20 + 1 = 4 and (70 - 30) / 20 + 1 = 3
  ASSERT_EQ(set.count(), 7);
  EXPECT_EQ(set.signals.shape, (std::vector<std::int64_t>{7, 2, 30}));
  EXPECT_EQ(set.class_index, (std::vector<int>{0, 0, 0, 0, 3, 3, 3}));
  EXPECT_EQ(set.recording_index, (std::vector<int>{0, 0, 0, 0, 1, 1, 1}));
  EXPECT_EQ(set.group_index[5], 1);
  // Segment 2 of recording a starts at sample 40; channel 1 is offset by 1000.
  EXPECT_EQ(set.signals.row(2)[0], 40.0f);
  EXPECT_EQ(set.signals.row(2)[30], 1040.0f);
  EXPECT_EQ(set.signals.row(2)[59], 1069.0f);
  ASSERT_EQ(set.context_names, (std::vector<std::string>{"scan_speed"}));
  EXPECT_EQ(set.context_values, (std::vector<double>{10.0, 13.0}));
}

TEST(Segmenter, HonoursTheCapPerRecording) {
  const SegmentSet set = segment_recordings({ramp_recording("a", 0, 1, 1000)}, {100, 50, 5});
  EXPECT_EQ(set.count(), 5);
}

TEST(Segmenter, RejectsMixedChannelCountsAndBadSpecs) {
  EXPECT_THROW(segment_recordings({ramp_recording("a", 0, 2, 100), ramp_recording("b", 1, 3, 100)}, {30, 30, 0}),
               DatasetError);
  EXPECT_THROW(segment_recordings({ramp_recording("a", 0, 2, 100)}, {0, 30, 0}), DatasetError);
  Recording broken = ramp_recording("c", 0, 2, 100);
  broken.signal.pop_back();
  EXPECT_THROW(segment_recordings({broken}, {30, 30, 0}), DatasetError);
}

}  // namespace
}  // namespace fscil
