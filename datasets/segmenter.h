#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "datasets/float_array.h"
#include "datasets/recording.h"

namespace fscil {

struct SegmentSpec {
  std::int64_t length = 0;  // samples per segment
  std::int64_t hop = 0;     // samples between segment starts
  std::int64_t max_per_recording = 0;  // 0 = as many as fit
};

// Segments of many recordings with the bookkeeping every later stage needs.
struct SegmentSet {
  FloatArray signals;                   // N x C x length
  std::vector<int> class_index;         // per segment
  std::vector<int> group_index;         // per segment
  std::vector<int> recording_index;     // per segment, into recording_ids
  std::vector<std::string> recording_ids;
  std::vector<SplitHint> recording_split;  // per recording
  std::vector<std::string> context_names;  // union of context keys, sorted
  std::vector<double> context_values;      // recordings x context_names (NaN where unknown)

  std::int64_t count() const { return static_cast<std::int64_t>(class_index.size()); }
};

// Cuts every recording into fixed-length segments. Recordings must share a channel count.
SegmentSet segment_recordings(const std::vector<Recording>& recordings, const SegmentSpec& spec);

}  // namespace fscil
