#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "datasets/segmenter.h"
#include "protocols/session_plan.h"

namespace fscil {

enum class SplitMode { recording, segment };
SplitMode parse_split_mode(const std::string& text);

// Which split a run scores after every session: the test split (numbers to report), or the
// validation split of every class (the protocol defaults are chosen on; never the test split).
enum class EvaluationSplit { test, validation };
EvaluationSplit parse_evaluation_split(const std::string& text);
std::string to_string(EvaluationSplit split);

// Which segments each session trains on, and the validation and test segments, as indices
// into a SegmentSet. Labels are protocol class indices.
struct SessionSchedule {
  SessionPlan plan;
  std::vector<std::vector<std::int64_t>> train;  // per session: base = all train segments, else K shots per class
  std::vector<std::int64_t> validation;          // base classes' validation segments (what methods may read)
  std::vector<std::int64_t> test;                // test segments of every class of the plan
  // Validation segments of every class of the plan, drawn from the contexts its test segments
  // come from: what `--evaluate-on validation` scores instead of `test`. No method reads them.
  std::vector<std::int64_t> scored_validation;
  // Classes (dataset names) with no validation recordings in their test contexts, in plan order.
  std::vector<std::string> classes_without_scored_validation;
  std::vector<int> label;                        // per segment: protocol class, -1 when unused

  std::vector<std::int64_t> labels_of(const std::vector<std::int64_t>& indices) const;
  // The segments a run scores: `test`, or `scored_validation` (throws ProtocolError naming the
  // classes that have none).
  const std::vector<std::int64_t>& scored_segments(EvaluationSplit split) const;
};

// Per class 60/20/20 train/validation/test. In recording mode whole recordings go to one side
// (neighbouring slices leak); a dataset's own test recordings never reach training or shots, and
// its own validation recordings, when it lists them, are the validation split;
// recordings in held-out contexts (context value held_out = 1) feed only the test set, the
// shots of novel classes and the scored validation of every class. Shots are drawn from each
// novel class's train part with the seed.
SessionSchedule build_session_schedule(const SegmentSet& segments, const std::vector<std::string>& class_names,
                                       const SessionPlan& plan, SplitMode mode, std::uint64_t seed);

}  // namespace fscil
