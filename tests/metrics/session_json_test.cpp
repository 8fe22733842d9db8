// The one serialiser of session results: result files write values that are not finite as null,
// checkpoints as texts that read back exactly; both forms read back through the same reader.
#include "metrics/session_json.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "metrics/session_fields.h"

namespace fscil {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

SessionOutcome diverged_session() {
  SessionOutcome session;
  session.session = 2;
  session.seen_classes = 7;
  session.accuracy = {61.25, 70.5, 40.0, 38.75, 2 * 70.5 * 40.0 / 110.5, 800};  // harmonic of base and novel
  session.train_seconds = 0.1 + 0.2;  // not exact in decimal: must still read back to the bit
  session.test_seconds = 0.25;
  session.context_ratio_mean = 1.5;
  session.diagnostics = {{"loss", -kInfinity}, {"ce", std::numeric_limits<double>::quiet_NaN()}};
  session.training_log = {{"session 2", 3, {{"loss", kInfinity}, {"lr", 1e-4}}}};
  return session;
}

TEST(SessionJson, ResultFilesWriteWhatIsNotFiniteAsNullAndCheckpointsAsText) {
  const nlohmann::json result_file = sessions_json({diverged_session()}, NonFinite::null);
  const nlohmann::json checkpoint = sessions_json({diverged_session()}, NonFinite::text);
  EXPECT_EQ(result_file[0]["diagnostics"].dump(), R"({"ce":null,"loss":null})");
  EXPECT_EQ(checkpoint[0]["diagnostics"].dump(), R"({"ce":"nan","loss":"-inf"})");
  EXPECT_TRUE(result_file[0]["context_ratio_max"].is_null());
  EXPECT_EQ(checkpoint[0]["context_ratio_max"], "nan");
  EXPECT_EQ(checkpoint[0]["training_log"][0]["values"]["loss"], "inf");
  EXPECT_EQ(result_file[0]["test_samples"].dump(), "800");
  EXPECT_EQ(result_file[0]["seen_classes"].dump(), "7");
}

TEST(SessionJson, EveryFieldReadsBackExactlyFromTheCheckpointForm) {
  const SessionOutcome saved = diverged_session();
  const auto read = sessions_from_json(nlohmann::json::parse(sessions_json({saved}, NonFinite::text).dump()), "x");
  ASSERT_EQ(read.size(), 1u);
  for (const auto& field : session_fields()) {
    const double expected = field.value(saved), actual = field.value(read[0]);
    if (std::isnan(expected)) {
      EXPECT_TRUE(std::isnan(actual)) << field.key;
    } else {
      EXPECT_EQ(actual, expected) << field.key;
    }
  }
  EXPECT_EQ(read[0].accuracy.samples, 800);
  EXPECT_EQ(read[0].diagnostics.at("loss"), -kInfinity);
  EXPECT_TRUE(std::isnan(read[0].diagnostics.at("ce")));
  ASSERT_EQ(read[0].training_log.size(), 1u);
  EXPECT_EQ(read[0].training_log[0].stage, "session 2");
  EXPECT_EQ(read[0].training_log[0].epoch, 3);
  EXPECT_EQ(read[0].training_log[0].values.at("loss"), kInfinity);
  EXPECT_EQ(read[0].training_log[0].values.at("lr"), 1e-4);
}

TEST(SessionJson, TheResultFileFormReadsBackWithNaNWhereAValueWasNotFinite) {
  const auto read =
      sessions_from_json(nlohmann::json::parse(sessions_json({diverged_session()}, NonFinite::null).dump()), "x");
  EXPECT_TRUE(std::isnan(read[0].diagnostics.at("loss")));
  EXPECT_EQ(read[0].context_ratio_mean, 1.5);
  EXPECT_EQ(read[0].accuracy.harmonic, 2 * 70.5 * 40.0 / 110.5);
}

TEST(SessionJson, TheTableListsEveryScalarFieldOnceInTheTidyCsvOrder) {
  std::string keys, columns;
  for (const auto& field : session_fields()) {
    keys += std::string(field.key) + " ";
    if (field.column) columns += std::string(field.column) + " ";
  }
  EXPECT_EQ(keys, "session seen_classes accuracy base_accuracy novel_accuracy current_accuracy harmonic_mean "
                  "test_samples train_seconds test_seconds context_ratio_mean context_ratio_max ");
  EXPECT_EQ(columns, "session seen_classes accuracy base novel current harmonic_mean train_seconds test_seconds R ");
}

std::string refusal_of(const nlohmann::json& sessions) {
  try {
    sessions_from_json(sessions, "run.json");
  } catch (const Error& error) {
    return error.what();
  }
  return "accepted";
}

TEST(SessionJson, ACountBelowZeroOrATextWhereANumberBelongsIsAnErrorNamingTheOriginAndField) {
  nlohmann::json sessions = sessions_json({diverged_session()}, NonFinite::null);
  sessions[0]["seen_classes"] = -3;
  EXPECT_EQ(refusal_of(sessions), "run.json: seen_classes -3, expected a whole number from 0 to 2147483647");
  sessions = sessions_json({diverged_session()}, NonFinite::null);
  sessions[0]["diagnostics"]["loss"] = "-Infinity";
  EXPECT_EQ(refusal_of(sessions),
            "run.json: diagnostic loss \"-Infinity\", expected a number, null, \"nan\", \"inf\" or \"-inf\"");
  EXPECT_EQ(refusal_of(nlohmann::json::object()), "run.json: sessions {}, expected a list");
}

}  // namespace
}  // namespace fscil
