#include "protocols/session_schedule.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <string>
#include <map>
#include <set>

#include "core/parameter_set.h"
#include "core/error.h"

namespace fscil {
namespace {

// classes x recordings x segments_per_recording segments, recordings numbered globally.
SegmentSet synthetic_segments(int classes, int recordings, int per_recording) {
  SegmentSet set;
  for (int c = 0; c < classes; ++c) {
    for (int r = 0; r < recordings; ++r) {
      set.recording_ids.push_back("c" + std::to_string(c) + "r" + std::to_string(r));
      set.recording_split.push_back(SplitHint::none);
      for (int s = 0; s < per_recording; ++s) {
        set.class_index.push_back(c);
        set.group_index.push_back(0);
        set.recording_index.push_back(c * recordings + r);
      }
    }
  }
  return set;
}

std::vector<std::string> names(int classes) {
  std::vector<std::string> result;
  for (int c = 0; c < classes; ++c) result.push_back("class" + std::to_string(c));
  return result;
}

SessionPlan plan_for(int classes, SessionDefaults defaults, const ParameterSet& params = ParameterSet(),
                     std::uint64_t seed = 1) {
  return make_session_plan(classes, defaults, params, seed);
}

TEST(SessionPlan, FollowsTheDatasetProtocolAndItsOverrides) {
  const SessionPlan haptex = plan_for(120, {75, 5, 5, 10});
  EXPECT_EQ(haptex.total_classes(), 120);
  EXPECT_EQ(haptex.seen_after(0), 75);
  EXPECT_EQ(haptex.seen_after(9), 120);
  EXPECT_EQ(haptex.first_class_of(3), 85);
  EXPECT_EQ(haptex.session_of_class(74), 0);
  EXPECT_EQ(haptex.session_of_class(75), 1);
  EXPECT_EQ(haptex.session_of_class(119), 9);
  EXPECT_EQ(haptex.class_order.front(), 0);
  EXPECT_EQ(haptex.class_order.back(), 119);

  ParameterSet params;
  params.set("shot", "1");
  params.set("sessions", "4");
  const SessionPlan shorter = plan_for(120, {75, 5, 5, 10}, params);
  EXPECT_EQ(shorter.shot, 1);
  EXPECT_EQ(shorter.total_classes(), 90);

  params.set("sessions", "20");
  EXPECT_THROW(plan_for(120, {75, 5, 5, 10}, params), ProtocolError);
}

// Issue 71: FCIAC's LS-100 protocol (60 base classes, 9 sessions, 5-way), as its release removes
// them (docs/compared_methods.md, PA-PCT): session 2 removes 59 and 64, 4 removes 58 and 69, 6
// removes 57 and 74, 8 removes 56 and 79; 72 classes remain.
TEST(SessionPlan, TheClassVariableProtocolAddsInOddAndRemovesInEvenSessionsAsFciacDoes) {
  ParameterSet params;
  params.set("removal", "fciac");
  const SessionPlan ls100 = plan_for(100, {60, 5, 5, 9}, params);
  EXPECT_EQ(ls100.total_classes(), 80);
  for (int session : {1, 3, 5, 7}) EXPECT_TRUE(ls100.adds_classes(session)) << session;
  for (int session : {0, 2, 4, 6, 8}) EXPECT_FALSE(ls100.adds_classes(session)) << session;
  EXPECT_EQ(ls100.seen_after(1), 65);
  EXPECT_EQ(ls100.seen_after(2), 65);
  EXPECT_EQ(ls100.first_class_of(3), 65);
  EXPECT_EQ(ls100.first_class_of(2), ls100.seen_after(2)) << "a removing session adds nothing";
  EXPECT_EQ(ls100.session_of_class(64), 1);
  EXPECT_EQ(ls100.session_of_class(65), 3);
  EXPECT_EQ(ls100.session_of_class(79), 7);
  EXPECT_TRUE(ls100.removed_in(1).empty());
  EXPECT_EQ(ls100.removed_in(2), (std::vector<int>{59, 64}));
  EXPECT_EQ(ls100.removed_in(4), (std::vector<int>{58, 69}));
  EXPECT_EQ(ls100.removed_in(6), (std::vector<int>{57, 74}));
  EXPECT_EQ(ls100.removed_in(8), (std::vector<int>{56, 79}));
  EXPECT_EQ(ls100.removed_by(8), (std::vector<int>{56, 57, 58, 59, 64, 69, 74, 79}));
  EXPECT_EQ(ls100.present_after(8), 72);
  EXPECT_EQ(params.used().at("removal"), "fciac");
  EXPECT_EQ(describe_removal(ls100), "class-variable sessions (removal=fciac): sessions 1, 3, 5, 7 add 5 classes each; "
                                     "session 2 removes 59, 64; session 4 removes 58, 69; session 6 removes 57, 74; "
                                     "session 8 removes 56, 79; 72 of 80 classes remain");

  // Without it the plan is the add-only one, and `removal` is not read: a run's identity stays.
  ParameterSet plain;
  const SessionPlan add_only = plan_for(100, {60, 5, 5, 9}, plain);
  EXPECT_EQ(add_only.total_classes(), 100);
  EXPECT_TRUE(add_only.removed_by(8).empty());
  EXPECT_EQ(plain.used().count("removal"), 0u);
  EXPECT_EQ(describe_removal(add_only), "");

  params.set("removed_base", "2");
  params.set("removed_novel", "3");
  const SessionPlan more = plan_for(100, {60, 5, 5, 9}, params);
  EXPECT_EQ(more.removed_in(4), (std::vector<int>{56, 57, 67, 68, 69}));
  params.set("removed_base", "15");  // 4 removing sessions x 15 = every base class
  EXPECT_THROW(plan_for(100, {60, 5, 5, 9}, params), ProtocolError);
  params.set("removed_base", "1");
  params.set("removed_novel", "6");  // more than a session adds
  EXPECT_THROW(plan_for(100, {60, 5, 5, 9}, params), ProtocolError);
  params.set("removed_novel", "1");
  params.set("removal", "sometimes");
  EXPECT_THROW(plan_for(100, {60, 5, 5, 9}, params), ProtocolError);
}

TEST(SessionPlan, ShuffledOrderIsAPermutationDrawnFromTheSeed) {
  ParameterSet params;
  params.set("class_order", "shuffled");
  const SessionPlan one = plan_for(20, {10, 5, 5, 3}, params, 1);
  const SessionPlan again = plan_for(20, {10, 5, 5, 3}, params, 1);
  const SessionPlan other = plan_for(20, {10, 5, 5, 3}, params, 2);
  EXPECT_EQ(one.class_order, again.class_order);
  EXPECT_NE(one.class_order, other.class_order);
  auto sorted = one.class_order;
  std::sort(sorted.begin(), sorted.end());
  for (int c = 0; c < 20; ++c) EXPECT_EQ(sorted[c], c);
}

TEST(SessionSchedule, RecordingsNeverStraddleTrainValidationAndTest) {
  const SegmentSet segments = synthetic_segments(20, 10, 10);
  const SessionPlan plan = plan_for(20, {10, 5, 5, 3});
  const SessionSchedule schedule = build_session_schedule(segments, names(20), plan, SplitMode::recording, 3);

  std::map<int, std::set<std::string>> sides;  // recording -> which sides use it
  for (auto index : schedule.train[0]) sides[segments.recording_index[index]].insert("train");
  for (auto index : schedule.validation) sides[segments.recording_index[index]].insert("validation");
  for (auto index : schedule.test) sides[segments.recording_index[index]].insert("test");
  for (int s = 1; s < 3; ++s) {
    for (auto index : schedule.train[s]) sides[segments.recording_index[index]].insert("train");
  }
  for (const auto& [recording, used] : sides) EXPECT_EQ(used.size(), 1u) << "recording " << recording;

  // 10 recordings per class: 6 train, 2 validation, 2 test, 10 segments each.
  EXPECT_EQ(schedule.train[0].size(), 10u * 60u);
  EXPECT_EQ(schedule.validation.size(), 10u * 20u);
  EXPECT_EQ(schedule.test.size(), 20u * 20u);
  for (int s = 1; s < 3; ++s) {
    ASSERT_EQ(schedule.train[s].size(), 25u);
    std::map<std::int64_t, int> per_class;
    for (auto label : schedule.labels_of(schedule.train[s])) ++per_class[label];
    EXPECT_EQ(per_class.size(), 5u);
    for (const auto& [label, count] : per_class) {
      EXPECT_EQ(count, 5);
      EXPECT_EQ(plan.session_of_class(static_cast<int>(label)), s);
    }
  }
  for (auto label : schedule.labels_of(schedule.validation)) EXPECT_LT(label, 10);
}

TEST(SessionSchedule, ShotsComeFromTheSeedAndTheSameSeedRepeats) {
  const SegmentSet segments = synthetic_segments(20, 10, 10);
  const SessionPlan plan = plan_for(20, {10, 5, 5, 3});
  const auto first = build_session_schedule(segments, names(20), plan, SplitMode::recording, 5);
  const auto again = build_session_schedule(segments, names(20), plan, SplitMode::recording, 5);
  const auto other = build_session_schedule(segments, names(20), plan, SplitMode::recording, 6);
  EXPECT_EQ(first.train, again.train);
  EXPECT_EQ(first.test, again.test);
  EXPECT_NE(first.train[1], other.train[1]);
}

TEST(SessionSchedule, DatasetTestRecordingsNeverReachTrainingOrShots) {
  SegmentSet segments = synthetic_segments(15, 8, 4);
  for (std::size_t r = 0; r < segments.recording_split.size(); ++r) {
    segments.recording_split[r] = (r % 8) < 4 ? SplitHint::train : SplitHint::test;
  }
  const SessionPlan plan = plan_for(15, {5, 5, 3, 3});
  const auto schedule = build_session_schedule(segments, names(15), plan, SplitMode::recording, 1);
  for (const auto& session : schedule.train) {
    for (auto index : session) EXPECT_EQ(segments.recording_split[segments.recording_index[index]], SplitHint::train);
  }
  for (auto index : schedule.validation) {
    EXPECT_EQ(segments.recording_split[segments.recording_index[index]], SplitHint::train);
  }
  for (auto index : schedule.test) EXPECT_EQ(segments.recording_split[segments.recording_index[index]], SplitHint::test);
}

TEST(SessionSchedule, ListedTrainValidationAndTestAreKeptAsPublished) {
  SegmentSet segments = synthetic_segments(15, 8, 1);  // one clip per recording, as in LS-100
  const SplitHint listed[8] = {SplitHint::train, SplitHint::train, SplitHint::train, SplitHint::train,
                               SplitHint::train, SplitHint::validation, SplitHint::test, SplitHint::test};
  for (std::size_t r = 0; r < segments.recording_split.size(); ++r) segments.recording_split[r] = listed[r % 8];
  const SessionPlan plan = plan_for(15, {5, 5, 3, 3});
  const auto schedule = build_session_schedule(segments, names(15), plan, SplitMode::recording, 1);
  auto split_of = [&](std::int64_t index) { return segments.recording_split[segments.recording_index[index]]; };
  EXPECT_EQ(schedule.train[0].size(), 5u * 5u);  // every listed training clip of the base classes
  for (const auto& session : schedule.train) {
    for (auto index : session) EXPECT_EQ(split_of(index), SplitHint::train);
  }
  EXPECT_EQ(schedule.train[1].size(), 5u * 3u);
  EXPECT_EQ(schedule.validation.size(), 5u);
  for (auto index : schedule.validation) EXPECT_EQ(split_of(index), SplitHint::validation);
  EXPECT_EQ(schedule.test.size(), 15u * 2u);
  for (auto index : schedule.test) EXPECT_EQ(split_of(index), SplitHint::test);
}

TEST(SessionSchedule, HeldOutContextsFeedOnlyShotsAndTests) {
  SegmentSet segments = synthetic_segments(15, 10, 3);
  segments.context_names = {"device", "held_out"};
  for (std::size_t r = 0; r < segments.recording_ids.size(); ++r) {
    const bool held_out = r % 10 >= 6;
    segments.context_values.push_back(held_out ? 3 : 0);
    segments.context_values.push_back(held_out ? 1 : 0);
  }
  auto held_out = [&](std::int64_t index) { return segments.recording_index[index] % 10 >= 6; };
  const SessionPlan plan = plan_for(15, {5, 5, 5, 3});
  const auto schedule = build_session_schedule(segments, names(15), plan, SplitMode::recording, 1);
  for (auto index : schedule.train[0]) EXPECT_FALSE(held_out(index));
  for (auto index : schedule.validation) EXPECT_FALSE(held_out(index));
  for (int s = 1; s < 3; ++s) {
    ASSERT_EQ(schedule.train[s].size(), 25u);
    for (auto index : schedule.train[s]) EXPECT_TRUE(held_out(index));
  }
  // 4 held-out recordings per class: 2 for the test, 2 for the shots of novel classes.
  EXPECT_EQ(schedule.test.size(), 15u * 2 * 3);
  std::set<int> test_recordings, shot_recordings;
  for (auto index : schedule.test) {
    EXPECT_TRUE(held_out(index));
    test_recordings.insert(segments.recording_index[index]);
  }
  for (int s = 1; s < 3; ++s) {
    for (auto index : schedule.train[s]) shot_recordings.insert(segments.recording_index[index]);
  }
  for (int recording : shot_recordings) EXPECT_EQ(test_recordings.count(recording), 0u);
}

TEST(SessionSchedule, ScoredValidationMirrorsTheTestSplitOfEveryClassAndNeverOverlapsIt) {
  // Without held-out contexts: every class's 20% validation recordings, base classes' being the
  // validation methods read.
  const SegmentSet open = synthetic_segments(20, 10, 10);
  const SessionPlan plan = plan_for(20, {10, 5, 5, 3});
  const SessionSchedule schedule = build_session_schedule(open, names(20), plan, SplitMode::recording, 3);
  EXPECT_EQ(schedule.scored_validation.size(), 20u * 20u);
  std::set<std::int64_t> scored(schedule.scored_validation.begin(), schedule.scored_validation.end());
  for (auto index : schedule.validation) EXPECT_EQ(scored.count(index), 1u);
  for (auto index : schedule.test) EXPECT_EQ(scored.count(index), 0u);
  for (int s = 0; s < 3; ++s) {
    for (auto index : schedule.train[s]) EXPECT_EQ(scored.count(index), 0u);
  }
  EXPECT_EQ(&schedule.scored_segments(EvaluationSplit::validation), &schedule.scored_validation);
  EXPECT_EQ(&schedule.scored_segments(EvaluationSplit::test), &schedule.test);

  // Held-out contexts (4 held-out recordings of 10 segments per class): 2 test; a base class
  // validates on the other 2, a novel class on 1 and draws its shots from the last one.
  SegmentSet shifted = synthetic_segments(15, 10, 10);
  shifted.context_names = {"device", "held_out"};
  for (std::size_t r = 0; r < shifted.recording_ids.size(); ++r) {
    shifted.context_values.push_back(r % 10 >= 6 ? 3 : 0);
    shifted.context_values.push_back(r % 10 >= 6 ? 1 : 0);
  }
  const SessionPlan shifted_plan = plan_for(15, {5, 5, 5, 3});
  const auto held = build_session_schedule(shifted, names(15), shifted_plan, SplitMode::recording, 1);
  std::map<std::int64_t, std::set<int>> validation_recordings, shot_recordings, test_recordings;
  for (auto index : held.scored_validation) {
    EXPECT_GE(shifted.recording_index[index] % 10, 6);  // the test's (held-out) contexts
    validation_recordings[held.label[index]].insert(shifted.recording_index[index]);
  }
  for (auto index : held.test) test_recordings[held.label[index]].insert(shifted.recording_index[index]);
  for (int s = 1; s < 3; ++s) {
    for (auto index : held.train[s]) shot_recordings[held.label[index]].insert(shifted.recording_index[index]);
  }
  for (std::int64_t label = 0; label < 15; ++label) {
    EXPECT_EQ(validation_recordings[label].size(), label < 5 ? 2u : 1u) << label;
    for (int recording : validation_recordings[label]) {
      EXPECT_EQ(test_recordings[label].count(recording), 0u);
      EXPECT_EQ(shot_recordings[label].count(recording), 0u);
    }
  }
  EXPECT_TRUE(held.classes_without_scored_validation.empty());

  // With too few segments left for the shots, a novel class keeps both recordings for them and
  // has no validation: scoring on validation is refused, naming it.
  SegmentSet sparse = synthetic_segments(15, 10, 3);
  sparse.context_names = shifted.context_names;
  sparse.context_values = shifted.context_values;
  const auto starved = build_session_schedule(sparse, names(15), shifted_plan, SplitMode::recording, 1);
  EXPECT_EQ(starved.classes_without_scored_validation.size(), 10u);
  try {
    starved.scored_segments(EvaluationSplit::validation);
    ADD_FAILURE() << "scored a split some classes lack";
  } catch (const ProtocolError& error) {
    EXPECT_NE(std::string(error.what()).find("10 of 15 classes have no validation recordings"), std::string::npos)
        << error.what();
  }
}

TEST(SessionSchedule, SegmentModeSplitsSegmentsSixtyTwentyTwenty) {
  const SegmentSet segments = synthetic_segments(20, 2, 10);
  const auto schedule = build_session_schedule(segments, names(20), plan_for(20, {10, 5, 5, 3}), SplitMode::segment, 1);
  EXPECT_EQ(schedule.train[0].size(), 10u * 12u);
  EXPECT_EQ(schedule.test.size(), 20u * 4u);
  EXPECT_THROW(build_session_schedule(segments, names(20), plan_for(20, {10, 5, 5, 3}), SplitMode::recording, 1),
               ProtocolError);
}

TEST(SessionSchedule, TooFewShotsNameTheClass) {
  const SegmentSet segments = synthetic_segments(20, 5, 1);  // 3 training segments per class
  try {
    build_session_schedule(segments, names(20), plan_for(20, {10, 5, 5, 3}), SplitMode::recording, 1);
    FAIL() << "expected an error";
  } catch (const ProtocolError& error) {
    EXPECT_NE(std::string(error.what()).find("class10: 3 training segments, 5 shots needed"), std::string::npos);
  }
}

TEST(ParameterSet, RemembersEveryReadAndRejectsMalformedValues) {
  ParameterSet params;
  params.set_assignment("pretrain_epochs=7");
  params.set_assignment("typo_key=1");
  EXPECT_EQ(params.integer("pretrain_epochs", 100, ValidRange::at_least(0)), 7);
  EXPECT_DOUBLE_EQ(params.real("temperature", 16.0, ValidRange::above(0)), 16.0);
  EXPECT_EQ(params.used().at("temperature"), "16");
  EXPECT_EQ(params.unread_keys(), (std::vector<std::string>{"typo_key"}));
  params.set("lr", "fast");
  EXPECT_THROW(params.real("lr", 0.1, ValidRange::any()), ProtocolError);
  params.set("order", "sideways");
  EXPECT_THROW(params.choice("order", "natural", {"natural", "shuffled"}), ProtocolError);
  EXPECT_THROW(params.set_assignment("no_equals_sign"), ProtocolError);
}

std::string refusal(const std::string& key, const std::string& value, const std::function<void(const ParameterSet&)>& read) {
  ParameterSet params;
  params.set(key, value);
  try {
    read(params);
  } catch (const ProtocolError& error) {
    return error.what();
  }
  return "accepted";
}

TEST(ParameterSet, RefusesValuesOutsideWhatTheirOwnerSaysIsValid) {
  const auto temperature = [](const ParameterSet& p) { p.real("temperature", 16, ValidRange::above(0)); };
  EXPECT_EQ(refusal("temperature", "0", temperature), "parameter temperature='0': expected a number > 0");
  EXPECT_EQ(refusal("temperature", "nan", temperature), "parameter temperature='nan': expected a finite number");
  EXPECT_EQ(refusal("temperature", "0.5", temperature), "accepted");
  const auto gamma = [](const ParameterSet& p) { p.real("lr_gamma", 0.5, ValidRange::above_up_to(0, 1)); };
  EXPECT_EQ(refusal("lr_gamma", "-1", gamma), "parameter lr_gamma='-1': expected a number in (0, 1]");
  EXPECT_EQ(refusal("lr_gamma", "1", gamma), "accepted");
  const auto mask = [](const ParameterSet& p) { p.real("orco_mask_time", 0.1, ValidRange::from_up_to(0, 1)); };
  EXPECT_EQ(refusal("orco_mask_time", "1", mask), "parameter orco_mask_time='1': expected a number in [0, 1)");
  const auto shots = [](const ParameterSet& p) { p.integer("shot", 5, ValidRange::at_least(1)); };
  EXPECT_EQ(refusal("shot", "0", shots), "parameter shot='0': expected an integer >= 1");
  EXPECT_EQ(refusal("shot", "1", shots), "accepted");
  // Training runs in float: what float cannot hold is refused with the name, not where it overflows.
  const auto any = [](const ParameterSet& p) { p.real("x", 0, ValidRange::any()); };
  EXPECT_EQ(refusal("x", "-3e38", any), "accepted");
  EXPECT_EQ(refusal("x", "-1e300", any),
            "parameter x='-1e300': expected a number of at most 3.40282e+38 in magnitude (training runs in 32-bit floats)");
}

// A --config file's value is named by the file; one the command line replaced is still checked for
// its form, not against a range that may follow from the values that replaced others.
TEST(ParameterSet, NamesAValuesOriginAndChecksTheFormOfValuesReplacedBeforeAnyRead) {
  const auto read = [](const std::function<void(ParameterSet&)>& give, const std::function<void(const ParameterSet&)>& use) {
    ParameterSet params;
    give(params);
    try {
      use(params);
    } catch (const ProtocolError& error) {
      return std::string(error.what());
    }
    return std::string("accepted");
  };
  const std::string file = "--config run.json: \"set\"";
  const auto removed = [](const ParameterSet& p) { p.count("removed_novel", 2, ValidRange::between(0, 5)); };
  EXPECT_EQ(read([&](ParameterSet& p) { p.set("removed_novel", "9", file); }, removed),
            "--config run.json: \"set\".removed_novel='9': expected an integer in [0, 5]");
  const auto replaced = [&](const std::string& value) {
    return [&file, value](ParameterSet& p) {
      p.set("removed_novel", "2");
      p.check_also("removed_novel", value, file);
    };
  };
  EXPECT_EQ(read(replaced("6"), removed), "accepted");  // in range for the way the file gave, not the one used
  EXPECT_EQ(read(replaced("abc"), removed), "--config run.json: \"set\".removed_novel='abc': expected an integer");
  EXPECT_EQ(read(replaced("3000000000"), removed),
            "--config run.json: \"set\".removed_novel='3000000000': expected an integer in [0, 5] and at most 2147483647");
  const auto lr = [](const ParameterSet& p) { p.real("lr", 0.1, ValidRange::above(0)); };
  EXPECT_EQ(read([&](ParameterSet& p) { p.set("lr", "0.2"); p.check_also("lr", "nan", file); }, lr),
            "--config run.json: \"set\".lr='nan': expected a finite number");
  const auto order = [](const ParameterSet& p) { p.choice("order", "natural", {"natural", "shuffled"}); };
  EXPECT_EQ(read([&](ParameterSet& p) { p.set("order", "natural"); p.check_also("order", "sideways", file); }, order),
            "--config run.json: \"set\".order='sideways': expected one of natural, shuffled");
  const auto flag = [](const ParameterSet& p) { p.flag("save", false); };
  EXPECT_EQ(read([&](ParameterSet& p) { p.set("save", "true"); p.check_also("save", "maybe", file); }, flag),
            "--config run.json: \"set\".save='maybe': expected true or false");
  EXPECT_EQ(read([&](ParameterSet& p) { p.set("save", "true"); p.check_also("save", "off", file); }, flag), "accepted");
}

}  // namespace
}  // namespace fscil
