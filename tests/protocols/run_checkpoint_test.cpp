// Checkpoints read back exactly what was saved, and a damaged or forged one is one ProtocolError
// naming the file, never a crash or a wild allocation (cases found by tests/fuzz).
#include "protocols/run_checkpoint.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <sstream>

#include "datasets/stable_hash.h"
#include "protocols/protocol_error.h"
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
  write_text(path, "fscil-bench checkpoint 2\n" + std::to_string(body.size()) + " " + stable_hash(body) + "\n" + body);
}

std::string body_of(const fs::path& path) {
  const std::string whole = read_text(path);
  return whole.substr(whole.find('\n', whole.find('\n') + 1) + 1);
}

torch::Tensor text_tensor(const std::string& text) {
  return torch::tensor(std::vector<std::int64_t>(text.begin(), text.end()), torch::kLong);
}

#define EXPECT_MENTIONS(message, fragment) EXPECT_NE((message).find(fragment), std::string::npos) << (message)

TEST(RunCheckpoint, NanInfiniteAndSubnormalDiagnosticsReadBack) {
  TemporaryDirectory directory;
  const fs::path path = directory.path() / "run.ckpt";
  RunCheckpoint saved = one_session();
  saved.outcomes[0].diagnostics = {{"base_ce_mean", std::numeric_limits<double>::quiet_NaN()},
                                   {"side_loss_mean", -std::numeric_limits<double>::infinity()},
                                   {"tiny", std::numeric_limits<double>::denorm_min()}};
  save_checkpoint(path, saved);
  const RunCheckpoint loaded = load_checkpoint(path, "run");
  const auto& diagnostics = loaded.outcomes.at(0).diagnostics;
  EXPECT_TRUE(std::isnan(diagnostics.at("base_ce_mean")));
  EXPECT_EQ(diagnostics.at("side_loss_mean"), -std::numeric_limits<double>::infinity());
  EXPECT_EQ(diagnostics.at("tiny"), std::numeric_limits<double>::denorm_min());
  EXPECT_EQ(loaded.generator, saved.generator);
}

TEST(RunCheckpoint, AHeaderDeclaringMoreThanTheFileIsCorruptNotAnAllocation) {
  TemporaryDirectory directory;
  const fs::path path = directory.path() / "run.ckpt";
  for (const char* length : {"99999999999999999", "18446744073709551615", "-1"}) {
    write_text(path, std::string("fscil-bench checkpoint 2\n") + length + " 0123456789abcdef\nbody");
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

TEST(RunCheckpoint, SessionResultsOfAnotherShapeOrWithNoWholeCountsAreRefused) {
  TemporaryDirectory directory;
  const fs::path path = directory.path() / "run.ckpt";
  torch::Tensor nan_session = torch::zeros({1, 12}, torch::kDouble);
  nan_session[0][0] = std::numeric_limits<double>::quiet_NaN();
  torch::Tensor huge_samples = torch::zeros({1, 12}, torch::kDouble);
  huge_samples[0][7] = 1e300;
  for (const torch::Tensor& rows : {torch::zeros({2, 5}, torch::kDouble), torch::zeros({1, 12}, torch::kFloat),
                                    torch::zeros({12}, torch::kDouble), nan_session, huge_samples}) {
    torch::serialize::OutputArchive archive;
    archive.write("identity", text_tensor("run"));
    archive.write("outcomes", rows);
    std::ostringstream body;
    archive.save_to(body);
    write_with_header(path, body.str());
    EXPECT_MENTIONS(load_error(path), "run.ckpt: corrupt checkpoint (session results are not N x 12 values");
  }
}

}  // namespace
}  // namespace fscil
