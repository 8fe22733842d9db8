// Checkpoints read back exactly what was saved, and a damaged or forged one is one ProtocolError
// naming the file, never a crash or a wild allocation (cases found by tests/fuzz).
#include "protocols/run_checkpoint.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <optional>
#include <sstream>

#include "core/stable_hash.h"
#include "core/error.h"
#include "tests/fixtures/dataset_fixtures.h"
#include "tests/temporary_directory.h"

namespace fscil {
namespace {

namespace fs = std::filesystem;

RunCheckpoint one_session() {
  SessionOutcome outcome;
  outcome.accuracy = {60, 60, 0, 60, 0, 40};
  outcome.seen_classes = 3;
  return {"run", {outcome}, 1.5, {{"w", torch::ones({2, 3})}}, std::mt19937_64(3), torch::arange(4, torch::kUInt8)};
}

std::string load_error(const fs::path& path) {
  try {
    load_checkpoint(path, "run");
  } catch (const ProtocolError& error) {
    return error.what();
  }
  return "no error";
}

// `body` behind the header save_checkpoint writes, so that it passes the length and digest check.
void write_with_header(const fs::path& path, const std::string& body) {
  write_text(path, "fscil-bench checkpoint 3\n" + std::to_string(body.size()) + " " + stable_hash(body) + "\n" + body);
}

std::string body_of(const fs::path& path) {
  const std::string whole = read_text(path);
  return whole.substr(whole.find('\n', whole.find('\n') + 1) + 1);
}

torch::Tensor text_tensor(const std::string& text) {
  return torch::tensor(std::vector<std::int64_t>(text.begin(), text.end()), torch::kLong);
}

#define EXPECT_MENTIONS(message, fragment) EXPECT_NE((message).find(fragment), std::string::npos) << (message)

// Found by tests/fuzz (fuzz_checkpoint_body): LibTorch wrote a state named "in" and could not read
// the file back. Such a name is now refused before anything is written.
TEST(RunCheckpoint, AStateNameLibTorchCannotReadBackIsRefusedBeforeWriting) {
  TemporaryDirectory dir;
  const fs::path path = dir.path() / "run.ckpt";
  RunCheckpoint checkpoint = one_session();
  checkpoint.method_state = {{"adapter.in.weight", torch::ones({2})}, {"encoder.stages.0.conv1.weight", torch::ones({3})}};
  try {
    save_checkpoint(path, checkpoint);
    FAIL() << "expected ProtocolError";
  } catch (const ProtocolError& error) {
    EXPECT_NE(std::string(error.what()).find("method state 'adapter.in.weight': 'in' is a Python keyword"),
              std::string::npos)
        << error.what();
  }
  EXPECT_FALSE(fs::exists(path));
  // Names that only contain a keyword, and digits as parts, read back.
  checkpoint.method_state = {{"inner.format.0.weight", torch::ones({2})}, {"if_gate", torch::ones({1})}};
  save_checkpoint(path, checkpoint);
  const RunCheckpoint loaded = load_checkpoint(path, "run");
  EXPECT_EQ(loaded.method_state.size(), 2u);
  EXPECT_TRUE(torch::equal(loaded.method_state.at("inner.format.0.weight"), torch::ones({2})));
}

TEST(RunCheckpoint, NanInfiniteAndSubnormalValuesReadBack) {
  TemporaryDirectory directory;
  const fs::path path = directory.path() / "run.ckpt";
  RunCheckpoint saved = one_session();
  saved.outcomes[0].diagnostics = {{"base_ce_mean", std::numeric_limits<double>::quiet_NaN()},
                                   {"side_loss_mean", -std::numeric_limits<double>::infinity()},
                                   {"tiny", std::numeric_limits<double>::denorm_min()}};
  saved.outcomes[0].context_ratio_max = std::numeric_limits<double>::infinity();
  saved.outcomes[0].train_seconds = 0.1 + 0.2;
  save_checkpoint(path, saved);
  const RunCheckpoint loaded = load_checkpoint(path, "run");
  const auto& diagnostics = loaded.outcomes.at(0).diagnostics;
  EXPECT_TRUE(std::isnan(diagnostics.at("base_ce_mean")));
  EXPECT_EQ(diagnostics.at("side_loss_mean"), -std::numeric_limits<double>::infinity());
  EXPECT_EQ(diagnostics.at("tiny"), std::numeric_limits<double>::denorm_min());
  EXPECT_TRUE(std::isnan(loaded.outcomes[0].context_ratio_mean));
  EXPECT_EQ(loaded.outcomes[0].context_ratio_max, std::numeric_limits<double>::infinity());
  EXPECT_EQ(loaded.outcomes[0].train_seconds, 0.1 + 0.2);
  EXPECT_EQ(loaded.outcomes[0].accuracy.samples, 40);
  EXPECT_EQ(loaded.outcomes[0].seen_classes, 3);
  EXPECT_EQ(loaded.generator, saved.generator);
}

// Each finished session's training log comes back as it was: stages with spaces, values
// exactly, a diverged loss as NaN, and epochs in order.
TEST(RunCheckpoint, TrainingLogsOfFinishedSessionsReadBack) {
  TemporaryDirectory directory;
  const fs::path path = directory.path() / "run.ckpt";
  RunCheckpoint saved = one_session();
  SessionOutcome second = saved.outcomes[0];
  second.session = 1;
  saved.outcomes.push_back(second);
  saved.outcomes[0].training_log = {{"pretrain", 1, {{"loss", 2.302585092994046}, {"lr", 0.1}}},
                                    {"pretrain", 2, {{"loss", 1.0 / 3}, {"lr", 0.05}, {"seconds", 12.5}}},
                                    {"pseudo-incremental", 1, {{"loss", 0.75}, {"selection_score", 61.25}}}};
  saved.outcomes[1].training_log = {{"session 1", 1, {{"loss", std::numeric_limits<double>::quiet_NaN()}}},
                                    {"session 1", 2, {{"loss", 4.9e-324}, {"lr", 1e-4}}}};
  save_checkpoint(path, saved);
  const RunCheckpoint loaded = load_checkpoint(path, "run");
  ASSERT_EQ(loaded.outcomes.size(), 2u);
  for (std::size_t s = 0; s < 2; ++s) {
    const auto& expected = saved.outcomes[s].training_log;
    const auto& actual = loaded.outcomes[s].training_log;
    ASSERT_EQ(actual.size(), expected.size()) << "session " << s;
    for (std::size_t e = 0; e < expected.size(); ++e) {
      EXPECT_EQ(actual[e].stage, expected[e].stage) << s << " " << e;
      EXPECT_EQ(actual[e].epoch, expected[e].epoch) << s << " " << e;
      ASSERT_EQ(actual[e].values.size(), expected[e].values.size()) << s << " " << e;
      for (const auto& [name, value] : expected[e].values) {
        if (std::isnan(value)) {
          EXPECT_TRUE(std::isnan(actual[e].values.at(name))) << name;
        } else {
          EXPECT_EQ(actual[e].values.at(name), value) << name;
        }
      }
    }
  }
}

// A checkpoint body as save_checkpoint writes it, with `sessions` as the finished sessions' text.
std::string body_with_sessions(const std::string& sessions) {
  torch::serialize::OutputArchive archive;
  archive.write("identity", text_tensor("run"));
  archive.write("sessions", text_tensor(sessions));
  archive.write("elapsed_seconds", torch::tensor(1.5, torch::kDouble));
  std::ostringstream generator;
  generator << std::mt19937_64(3);
  archive.write("generator", text_tensor(generator.str()));
  archive.write("torch_random_state", torch::arange(4, torch::kUInt8));
  torch::serialize::OutputArchive method;
  method.write("w", torch::ones({2, 3}));
  archive.write("method", method);
  std::ostringstream body;
  archive.save_to(body);
  return body.str();
}

constexpr const char* kSessionFields =
    R"("session":0,"seen_classes":3,"accuracy":60.0,"base_accuracy":60.0,"novel_accuracy":0.0,)"
    R"("current_accuracy":60.0,"harmonic_mean":0.0,"test_samples":40,"train_seconds":1.0,"test_seconds":0.5,)"
    R"("context_ratio_mean":null,"context_ratio_max":"inf")";

TEST(RunCheckpoint, ASessionWithoutDiagnosticsOrTrainingLogReadsWithNone) {
  TemporaryDirectory directory;
  const fs::path path = directory.path() / "run.ckpt";
  write_with_header(path, body_with_sessions(fmt::format("[{{{}}}]", kSessionFields)));
  const RunCheckpoint loaded = load_checkpoint(path, "run");
  ASSERT_EQ(loaded.outcomes.size(), 1u);
  EXPECT_TRUE(loaded.outcomes[0].training_log.empty());
  EXPECT_TRUE(loaded.outcomes[0].diagnostics.empty());
  EXPECT_EQ(loaded.outcomes[0].accuracy.samples, 40);
  EXPECT_EQ(loaded.outcomes[0].context_ratio_max, std::numeric_limits<double>::infinity());
  EXPECT_EQ(loaded.elapsed_seconds, 1.5);
}

TEST(RunCheckpoint, SessionResultsThatTheSerialiserDidNotWriteAreRefused) {
  TemporaryDirectory directory;
  const fs::path path = directory.path() / "run.ckpt";
  const std::string fields = kSessionFields;
  const auto with = [&](const std::string& from, const std::string& to) {
    std::string text = fields;
    text.replace(text.find(from), from.size(), to);
    return "[{" + text + "}]";
  };
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"[{", "session results: "},
      {"{}", "sessions {}, expected a list"},
      {"[{}]", "session results: "},
      {with("\"session\":0", "\"session\":-1"), "session -1, expected a whole number from 0"},
      {with("\"session\":0", "\"session\":0.5"), "session 0.5, expected a whole number"},
      {with("\"test_samples\":40", "\"test_samples\":1e300"), "test_samples 1e+300, expected a whole number"},
      {with("\"accuracy\":60.0", "\"accuracy\":150.0"), "session 0 has an accuracy of 150"},
      {with("\"accuracy\":60.0", "\"accuracy\":\"nan\""), "accuracy \"nan\", expected a number"},
      {with("\"context_ratio_max\":\"inf\"", "\"context_ratio_max\":\"huge\""),
       "context_ratio_max \"huge\", expected a number, null"},
      {"[{" + fields + R"(,"diagnostics":{"loss":"x"}}])", "diagnostic loss \"x\", expected a number"},
      {"[{" + fields + R"(,"training_log":[{"stage":"pre,train","epoch":1,"values":{}}]}])",
       "training log stage 'pre,train', expected text without commas"},
  };
  for (const auto& [sessions, fragment] : cases) {
    write_with_header(path, body_with_sessions(sessions));
    const std::string error = load_error(path);
    EXPECT_MENTIONS(error, "run.ckpt: corrupt checkpoint") << sessions;
    EXPECT_MENTIONS(error, fragment) << sessions;
  }
}

TEST(RunCheckpoint, ACheckpointOfAnEarlierFormatSaysWhichAndWhatToDo) {
  TemporaryDirectory directory;
  const fs::path path = directory.path() / "run.ckpt";
  write_text(path, "fscil-bench checkpoint 2\n4 0123456789abcdef\nbody");
  EXPECT_EQ(load_error(path), path.string() + ": fscil-bench checkpoint 2, this version reads fscil-bench checkpoint "
                                             "3; delete it to start that run over");
}

TEST(RunCheckpoint, AHeaderDeclaringMoreThanTheFileIsCorruptNotAnAllocation) {
  TemporaryDirectory directory;
  const fs::path path = directory.path() / "run.ckpt";
  for (const char* length : {"99999999999999999", "18446744073709551615", "-1"}) {
    write_text(path, std::string("fscil-bench checkpoint 3\n") + length + " 0123456789abcdef\nbody");
    EXPECT_MENTIONS(load_error(path), "run.ckpt: corrupt checkpoint (truncated, altered") << length;
  }
}

TEST(RunCheckpoint, AnArchiveLibTorchCannotImportIsAProtocolError) {
  TemporaryDirectory directory;
  const fs::path path = directory.path() / "run.ckpt";
  save_checkpoint(path, one_session());
  std::string body = body_of(path);
  const auto at = body.find("c__torch__");
  ASSERT_NE(at, std::string::npos);
  body.replace(at, 10, "c_dtorch__");  // its TorchScript importer throws an ErrorReport, no c10::Error
  write_with_header(path, body);
  EXPECT_MENTIONS(load_error(path), "run.ckpt: corrupt checkpoint (");
}

}  // namespace
}  // namespace fscil
