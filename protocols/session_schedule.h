#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "datasets/segmenter.h"
#include "protocols/session_plan.h"

namespace fscil {

enum class SplitMode { recording, segment };
SplitMode parse_split_mode(const std::string& text);

// Which segments each session trains on, and the validation and test segments, as indices
// into a SegmentSet. Labels are protocol class indices.
struct SessionSchedule {
  SessionPlan plan;
  std::vector<std::vector<std::int64_t>> train;  // per session: base = all train segments, else K shots per class
  std::vector<std::int64_t> validation;          // base classes' validation segments
  std::vector<std::int64_t> test;                // test segments of every class of the plan
  std::vector<int> label;                        // per segment: protocol class, -1 when unused

  std::vector<std::int64_t> labels_of(const std::vector<std::int64_t>& indices) const;
};

// Per class 60/20/20 train/validation/test. In recording mode whole recordings go to one side
// (neighbouring slices leak); a dataset's own test recordings never reach training or shots, and
// its own validation recordings, when it lists them, are the validation split;
// recordings in held-out contexts (context value held_out = 1) feed only the test set and the
// shots of novel classes. Shots are drawn from each novel class's train part with the seed.
SessionSchedule build_session_schedule(const SegmentSet& segments, const std::vector<std::string>& class_names,
                                       const SessionPlan& plan, SplitMode mode, std::uint64_t seed);

}  // namespace fscil
