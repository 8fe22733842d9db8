#include "protocols/session_schedule.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>

#include "core/error.h"
#include "core/seeded_shuffle.h"

namespace fscil {

namespace {

struct ClassSplit {
  std::vector<std::int64_t> train, validation, test;
  // Validation segments from the contexts of `test` (the scored validation split); for a base
  // class outside held-out contexts this is `validation` itself.
  std::vector<std::int64_t> scored_validation;
};

int share(std::size_t count, double fraction) {
  return std::max(1, static_cast<int>(std::lround(fraction * static_cast<double>(count))));
}

// Splits a list of units (recordings or segments) 60/20/20 after a seeded shuffle.
template <typename Unit>
void split_units(std::vector<Unit> units, std::mt19937_64& generator, std::vector<Unit>& train,
                 std::vector<Unit>& validation, std::vector<Unit>& test) {
  shuffle_with(units, generator);
  const int n_test = share(units.size(), 0.2), n_validation = share(units.size(), 0.2);
  test.assign(units.begin(), units.begin() + n_test);
  validation.assign(units.begin() + n_test, units.begin() + n_test + n_validation);
  train.assign(units.begin() + n_test + n_validation, units.end());
}

// Recordings marked held_out were acquired in contexts base training must never see.
std::vector<bool> held_out_recordings(const SegmentSet& segments) {
  std::vector<bool> held_out(segments.recording_ids.size(), false);
  const auto name = std::find(segments.context_names.begin(), segments.context_names.end(), "held_out");
  if (name == segments.context_names.end()) return held_out;
  const std::size_t column = name - segments.context_names.begin();
  for (std::size_t r = 0; r < held_out.size(); ++r) {
    held_out[r] = segments.context_values[r * segments.context_names.size() + column] == 1.0;
  }
  return held_out;
}

// Base-class training recordings, already shuffled: a quarter (at least one) validates, the rest train.
void split_train_validation(const std::vector<int>& open, const std::string& class_name, std::vector<int>& train,
                            std::vector<int>& validation) {
  if (open.size() < 2) {
    throw ProtocolError(fmt::format("class {}: {} training recordings, at least 2 needed for train and validation",
                                    class_name, open.size()));
  }
  const int n_validation = share(open.size(), 0.25);
  validation.assign(open.begin(), open.begin() + n_validation);
  train.assign(open.begin() + n_validation, open.end());
}

// Held-out contexts: half of those recordings test. Of the other half, a base class keeps them
// all as its scored validation (base training never sees them); a novel class gives a quarter
// (at least one) to its scored validation when the rest still holds `shots` segments, and draws
// its shots from the rest. Base classes train and validate on the other recordings only.
void split_around_held_out_contexts(std::vector<int> open, std::vector<int> held_out, bool base_class, int shots,
                                    const std::function<std::size_t(const std::vector<int>&)>& segments_in,
                                    std::mt19937_64& generator, const std::string& class_name,
                                    std::vector<int>& train, std::vector<int>& validation, std::vector<int>& test,
                                    std::vector<int>& scored_validation) {
  shuffle_with(open, generator);
  shuffle_with(held_out, generator);
  if (held_out.size() < 2) {
    throw ProtocolError(fmt::format("class {}: {} held-out-context recordings, at least 2 needed for shots and test",
                                    class_name, held_out.size()));
  }
  const std::size_t n_test = held_out.size() / 2;
  test.assign(held_out.begin(), held_out.begin() + n_test);
  const std::vector<int> rest(held_out.begin() + n_test, held_out.end());
  if (base_class) {
    if (open.size() < 2) {  // say why: the recordings are there, marked held out
      throw ProtocolError(fmt::format("class {}: {} recordings outside held-out contexts and {} marked held_out=1 (the "
                                      "manifest's context), at least 2 unmarked needed to train and validate a base "
                                      "class", class_name, open.size(), held_out.size()));
    }
    split_train_validation(open, class_name, train, validation);
    scored_validation = rest;
    return;
  }
  train = rest;
  if (rest.size() >= 2) {
    std::vector<int> shot_pool, carved;
    split_train_validation(rest, class_name, shot_pool, carved);
    if (segments_in(shot_pool) >= static_cast<std::size_t>(shots)) {
      train = shot_pool;
      scored_validation = carved;
    }
  }
}

ClassSplit split_class(const SegmentSet& segments, const std::vector<bool>& held_out,
                       const std::vector<std::int64_t>& members, SplitMode mode, bool base_class, int shots,
                       std::mt19937_64& generator, const std::string& class_name) {
  ClassSplit split;
  if (mode == SplitMode::segment) {
    if (members.size() < 3) {
      throw ProtocolError(fmt::format("class {}: {} segments, at least 3 needed for train/validation/test",
                                      class_name, members.size()));
    }
    split_units(members, generator, split.train, split.validation, split.test);
    split.scored_validation = split.validation;
    return split;
  }
  std::map<int, std::vector<std::int64_t>> by_recording;
  for (std::int64_t index : members) by_recording[segments.recording_index[index]].push_back(index);
  std::vector<int> open, dataset_test, dataset_validation, context_held_out;
  for (const auto& [recording, indices] : by_recording) {
    if (held_out[recording]) {
      context_held_out.push_back(recording);
    } else if (segments.recording_split[recording] == SplitHint::test) {
      dataset_test.push_back(recording);
    } else if (segments.recording_split[recording] == SplitHint::validation) {
      dataset_validation.push_back(recording);
    } else {
      open.push_back(recording);
    }
  }
  std::vector<int> train, validation, test, scored_validation;
  bool scored_is_validation = true;
  if (!context_held_out.empty()) {
    const auto segments_in = [&](const std::vector<int>& recordings) {
      std::size_t count = 0;
      for (int recording : recordings) count += by_recording[recording].size();
      return count;
    };
    split_around_held_out_contexts(open, context_held_out, base_class, shots, segments_in, generator, class_name,
                                   train, validation, test, scored_validation);
    scored_is_validation = false;
  } else if (!dataset_validation.empty()) {
    // The dataset's own lists (LS-100, NS-100): train, validation and test as published.
    if (dataset_test.empty() || open.empty()) {
      throw ProtocolError(fmt::format("class {}: the dataset lists {} validation, {} test and {} training recordings; "
                                      "at least one of each is needed", class_name, dataset_validation.size(),
                                      dataset_test.size(), open.size()));
    }
    train = open;
    validation = dataset_validation;
    test = dataset_test;
  } else if (!dataset_test.empty()) {
    test = dataset_test;  // the dataset's own test recordings
    shuffle_with(open, generator);
    split_train_validation(open, class_name, train, validation);
  } else {
    if (open.size() < 3) {
      throw ProtocolError(fmt::format("class {}: {} recordings, a split grouped by recording needs at least 3 "
                                      "(or use --split-mode segment)", class_name, open.size()));
    }
    split_units(open, generator, train, validation, test);
  }
  auto gather = [&](const std::vector<int>& recordings, std::vector<std::int64_t>& out) {
    for (int recording : recordings) {
      const auto& indices = by_recording[recording];
      out.insert(out.end(), indices.begin(), indices.end());
    }
    std::sort(out.begin(), out.end());
  };
  gather(train, split.train);
  gather(validation, split.validation);
  gather(test, split.test);
  if (scored_is_validation) {
    split.scored_validation = split.validation;
  } else {
    gather(scored_validation, split.scored_validation);
  }
  return split;
}

}  // namespace

SplitMode parse_split_mode(const std::string& text) {
  if (text == "recording") return SplitMode::recording;
  if (text == "segment") return SplitMode::segment;
  throw ProtocolError(fmt::format("split mode '{}': expected recording or segment", text));
}

EvaluationSplit parse_evaluation_split(const std::string& text) {
  if (text == "test") return EvaluationSplit::test;
  if (text == "validation") return EvaluationSplit::validation;
  throw ProtocolError(fmt::format("--evaluate-on '{}': expected test or validation", text));
}

std::string to_string(EvaluationSplit split) { return split == EvaluationSplit::test ? "test" : "validation"; }

const std::vector<std::int64_t>& SessionSchedule::scored_segments(EvaluationSplit split) const {
  if (split == EvaluationSplit::test) return test;
  if (!classes_without_scored_validation.empty()) {
    throw ProtocolError(fmt::format("--evaluate-on validation: {} of {} classes have no validation recordings in their "
                                    "test contexts (first: {}); this dataset can only be scored on test",
                                    classes_without_scored_validation.size(), plan.class_order.size(),
                                    classes_without_scored_validation.front()));
  }
  return scored_validation;
}

std::vector<std::int64_t> SessionSchedule::labels_of(const std::vector<std::int64_t>& indices) const {
  std::vector<std::int64_t> labels;
  labels.reserve(indices.size());
  for (std::int64_t index : indices) labels.push_back(label[index]);
  return labels;
}

SessionSchedule build_session_schedule(const SegmentSet& segments, const std::vector<std::string>& class_names,
                                       const SessionPlan& plan, SplitMode mode, std::uint64_t seed) {
  SessionSchedule schedule;
  schedule.plan = plan;
  schedule.train.assign(plan.sessions, {});
  schedule.label.assign(segments.count(), -1);

  std::map<int, int> protocol_class_of;
  for (int p = 0; p < static_cast<int>(plan.class_order.size()); ++p) protocol_class_of[plan.class_order[p]] = p;
  std::vector<std::vector<std::int64_t>> members(plan.class_order.size());
  for (std::int64_t i = 0; i < segments.count(); ++i) {
    const auto found = protocol_class_of.find(segments.class_index[i]);
    if (found == protocol_class_of.end()) continue;
    schedule.label[i] = found->second;
    members[found->second].push_back(i);
  }

  const std::vector<bool> held_out = held_out_recordings(segments);
  for (int p = 0; p < static_cast<int>(members.size()); ++p) {
    const int dataset_class = plan.class_order[p];
    const std::string name = dataset_class < static_cast<int>(class_names.size())
                                 ? class_names[dataset_class] : std::to_string(dataset_class);
    auto split_generator = seeded_generator(seed, SeedPurpose::split, static_cast<std::uint64_t>(dataset_class));
    const int session = plan.session_of_class(p);
    ClassSplit split =
        split_class(segments, held_out, members[p], mode, session == 0, plan.shot, split_generator, name);
    schedule.test.insert(schedule.test.end(), split.test.begin(), split.test.end());
    schedule.scored_validation.insert(schedule.scored_validation.end(), split.scored_validation.begin(),
                                      split.scored_validation.end());
    if (split.scored_validation.empty()) schedule.classes_without_scored_validation.push_back(name);
    if (session == 0) {
      schedule.train[0].insert(schedule.train[0].end(), split.train.begin(), split.train.end());
      schedule.validation.insert(schedule.validation.end(), split.validation.begin(), split.validation.end());
      continue;
    }
    if (static_cast<int>(split.train.size()) < plan.shot) {
      throw ProtocolError(fmt::format("class {}: {} training segments, {} shots needed", name, split.train.size(),
                                      plan.shot));
    }
    seeded_shuffle(split.train, seed, SeedPurpose::shots, static_cast<std::uint64_t>(dataset_class));
    split.train.resize(plan.shot);
    std::sort(split.train.begin(), split.train.end());
    auto& session_train = schedule.train[session];
    session_train.insert(session_train.end(), split.train.begin(), split.train.end());
  }
  return schedule;
}

}  // namespace fscil
