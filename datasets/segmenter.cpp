#include "datasets/segmenter.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "core/error.h"

namespace fscil {

namespace {

std::int64_t segments_in(const Recording& recording, const SegmentSpec& spec) {
  if (recording.length < spec.length) return 0;
  std::int64_t count = 1 + (recording.length - spec.length) / spec.hop;
  if (spec.max_per_recording > 0) count = std::min(count, spec.max_per_recording);
  return count;
}

}  // namespace

SegmentSet segment_recordings(const std::vector<Recording>& recordings, const SegmentSpec& spec) {
  if (spec.length <= 0 || spec.hop <= 0) {
    throw DatasetError(fmt::format("segment length {} and hop {} must be positive", spec.length,
                                   spec.hop));
  }
  if (recordings.empty()) throw DatasetError("no recordings to segment");
  const std::int64_t channels = recordings.front().channels;

  std::int64_t total = 0;
  std::set<std::string> context_keys;
  for (const auto& recording : recordings) {
    if (recording.channels != channels) {
      throw DatasetError(fmt::format("recording {}: {} channels, expected {} like the others",
                                     recording.id, recording.channels, channels));
    }
    if (static_cast<std::int64_t>(recording.signal.size()) != recording.channels * recording.length) {
      throw DatasetError(fmt::format("recording {}: signal holds {} values, expected {} x {}",
                                     recording.id, recording.signal.size(), recording.channels,
                                     recording.length));
    }
    total += segments_in(recording, spec);
    for (const auto& [key, value] : recording.context) context_keys.insert(key);
  }

  SegmentSet set;
  set.signals = FloatArray({total, channels, spec.length});
  set.context_names.assign(context_keys.begin(), context_keys.end());
  set.context_values.assign(recordings.size() * set.context_names.size(),
                            std::numeric_limits<double>::quiet_NaN());
  std::int64_t next = 0;
  for (std::size_t r = 0; r < recordings.size(); ++r) {
    const Recording& recording = recordings[r];
    set.recording_ids.push_back(recording.id);
    set.recording_split.push_back(recording.split_hint);
    for (std::size_t k = 0; k < set.context_names.size(); ++k) {
      const auto found = recording.context.find(set.context_names[k]);
      if (found != recording.context.end()) {
        set.context_values[r * set.context_names.size() + k] = found->second;
      }
    }
    const std::int64_t count = segments_in(recording, spec);
    for (std::int64_t s = 0; s < count; ++s, ++next) {
      float* out = set.signals.row(next);
      for (std::int64_t c = 0; c < channels; ++c) {
        const float* in = recording.signal.data() + c * recording.length + s * spec.hop;
        std::copy(in, in + spec.length, out + c * spec.length);
      }
      set.class_index.push_back(recording.class_index);
      set.group_index.push_back(recording.group_index);
      set.recording_index.push_back(static_cast<int>(r));
    }
  }
  return set;
}

}  // namespace fscil
