#include "reports/reference_numbers.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "core/atomic_file.h"
#include "core/error.h"
#include "tests/reports/session_runs.h"
#include "tests/temporary_directory.h"

namespace fscil {
namespace {

RunRecord run_of(const std::string& method, std::uint64_t seed, const std::vector<double>& accuracies) {
  return run_with_accuracies(method, "simtex-mini", seed, accuracies);
}

std::string message_of(const std::function<void()>& call) {
  try {
    call();
  } catch (const ReportError& error) {
    return error.what();
  }
  return "no error";
}

TEST(ReferenceNumbers, EveryValueOfEveryRunSurvivesTheFile) {
  const auto values = reference_values_of({run_of("prototype", 1, {60, 50, 40}), run_of("pits-sc", 2, {70, 65})}, 2.0);
  ASSERT_EQ(values.size(), 6u + 5u);  // acc_0..acc_2, AA, PD, ADR; acc_0..acc_1, AA, PD, ADR
  EXPECT_EQ(values[3].metric, "AA");
  EXPECT_DOUBLE_EQ(values[3].expected, 50.0);
  EXPECT_EQ(values[4].metric, "PD");
  EXPECT_DOUBLE_EQ(values[4].expected, 20.0);
  TemporaryDirectory directory;
  const auto path = directory.path() / "reference.csv";
  write_file_atomically(path, render_reference_csv(values, "bash regenerate.sh"));
  const auto loaded = load_reference_csv(path);
  ASSERT_EQ(loaded.size(), values.size());
  EXPECT_EQ(loaded[7].method, "pits-sc");
  EXPECT_EQ(loaded[7].seed, 2u);
  EXPECT_EQ(loaded[7].metric, "acc_1");
  EXPECT_DOUBLE_EQ(loaded[7].expected, 65.0);
  EXPECT_DOUBLE_EQ(loaded[7].tolerance, 2.0);
}

TEST(ReferenceNumbers, AGainIsAsSuspiciousAsALoss) {
  const auto reference = reference_values_of({run_of("prototype", 1, {60, 50, 40})}, 2.0);
  EXPECT_TRUE(check_against_reference({run_of("prototype", 1, {61.5, 48.5, 40})}, reference).failures.empty());
  const ReferenceCheck gain = check_against_reference({run_of("prototype", 1, {60, 50, 42.5})}, reference);
  // acc_2 +2.5 moves AA by +0.83 (within) and PD by -2.5 and ADR by -2.5 (outside).
  ASSERT_EQ(gain.failures.size(), 3u);
  EXPECT_EQ(gain.failures[0], "prototype on simtex-mini seed 1 acc_2: expected 40.00 +- 2.00, got 42.50 (+2.50)");
  const ReferenceCheck loss = check_against_reference({run_of("prototype", 1, {57, 50, 40})}, reference);
  EXPECT_NE(loss.failures.at(0).find("acc_0: expected 60.00 +- 2.00, got 57.00 (-3.00)"), std::string::npos);
  EXPECT_EQ(loss.values_checked, 6u);
}

TEST(ReferenceNumbers, MissingRunsAndOtherProtocolsFail) {
  const auto reference = reference_values_of({run_of("prototype", 1, {60, 50}), run_of("prototype", 2, {60, 50})}, 2.0);
  const ReferenceCheck missing = check_against_reference({run_of("prototype", 1, {60, 50})}, reference);
  ASSERT_EQ(missing.failures.size(), 1u);
  EXPECT_EQ(missing.failures[0], "prototype on simtex-mini seed 2: no result file for this run");
  RunRecord other = run_of("prototype", 1, {60, 50});
  other.threads = 1;
  const ReferenceCheck threads = check_against_reference({other, run_of("prototype", 2, {60, 50})}, reference);
  ASSERT_EQ(threads.failures.size(), 1u);
  EXPECT_NE(threads.failures[0].find("ran with profile smoke and 1 threads, the reference with smoke and 2"),
            std::string::npos);
}

TEST(ReferenceNumbers, Bf16RunsNeitherMakeNorMeetFp32References) {
  RunRecord bf16 = run_of("prototype", 1, {60, 50});
  bf16.protocol_parameters["precision"] = "bf16";
  EXPECT_THROW(reference_values_of({bf16}, 2.0), ReportError);
  const auto reference = reference_values_of({run_of("prototype", 1, {60, 50})}, 2.0);
  const ReferenceCheck check = check_against_reference({bf16}, reference);
  ASSERT_EQ(check.failures.size(), 1u);
  EXPECT_EQ(check.failures[0], "prototype on simtex-mini seed 1: made in bf16; reference numbers are fp32 runs' numbers");
}

RunRecord on_kernels(RunRecord record, const std::string& kernels) {
  record.machine["kernels"] = kernels;
  return record;
}

TEST(ReferenceNumbers, RunsAreComparedOnlyWithValuesOfTheirOwnKernels) {
  const std::string avx512 = "aten=AVX512 openblas=SkylakeX onednn=avx512_core";
  const std::string avx2 = "aten=AVX2 openblas=Zen onednn=avx2";
  const auto reference = reference_values_of({on_kernels(run_of("prototype", 1, {60, 50}), avx512)}, 2.0);
  TemporaryDirectory directory;
  const auto path = directory.path() / "reference.csv";
  write_file_atomically(path, render_reference_csv(reference, "bash regenerate.sh"));
  const auto loaded = load_reference_csv(path);
  EXPECT_EQ(loaded.at(0).kernels, avx512);

  const ReferenceCheck other = check_against_reference({on_kernels(run_of("prototype", 1, {60, 50}), avx2)}, loaded);
  ASSERT_EQ(other.failures.size(), 1u);
  EXPECT_EQ(other.values_checked, 0u);
  EXPECT_EQ(other.failures[0], "prototype on simtex-mini seed 1: ran on kernels " + avx2 +
                                   ", the reference holds values of kernels " + avx512 +
                                   "; values of other kernels are not compared (README, Reference numbers)");
  RunRecord unrecorded = run_of("prototype", 1, {60, 50});
  unrecorded.machine.erase("kernels");
  EXPECT_NE(check_against_reference({unrecorded}, loaded).failures.at(0).find("ran on kernels unrecorded"),
            std::string::npos);

  // A file holding both machines' values compares each run with its own kernels' values only.
  auto both = loaded;
  for (auto value : reference_values_of({on_kernels(run_of("prototype", 1, {40, 30}), avx2)}, 2.0)) {
    both.push_back(value);
  }
  const ReferenceCheck on_avx2 = check_against_reference({on_kernels(run_of("prototype", 1, {40, 30}), avx2)}, both);
  EXPECT_TRUE(on_avx2.failures.empty()) << on_avx2.failures.at(0);
  EXPECT_EQ(on_avx2.values_checked, 5u);
  const ReferenceCheck on_avx512 =
      check_against_reference({on_kernels(run_of("prototype", 1, {60, 50}), avx512)}, both);
  EXPECT_TRUE(on_avx512.failures.empty());
  EXPECT_EQ(on_avx512.values_checked, 5u);

  // A file written before kernels were recorded compares with runs on any kernels.
  std::ofstream(path) << "method,dataset,profile,seed,threads,metric,expected,tolerance\n"
                      << "prototype,simtex-mini,smoke,1,2,acc_0,60,2\n";
  const auto old = load_reference_csv(path);
  EXPECT_EQ(old.at(0).kernels, "");
  const ReferenceCheck any = check_against_reference({on_kernels(run_of("prototype", 1, {60, 50}), avx512)}, old);
  EXPECT_TRUE(any.failures.empty());
  EXPECT_EQ(any.values_checked, 1u);
  std::ofstream(path) << "method,dataset,profile,seed,threads,kernels,metric,expected,tolerance\n"
                      << "prototype,simtex-mini,smoke,1,2,acc_0,60,2\n";
  EXPECT_NE(message_of([&] { load_reference_csv(path); })
                .find("reference.csv:2: 8 fields, expected 9 (method,dataset,profile,seed,threads,kernels,metric,"),
            std::string::npos);
}

TEST(ReferenceNumbers, OnlyRunsThatRecordTheirKernelsMakeReferenceValues) {
  RunRecord old = run_of("prototype", 1, {60, 50});
  old.machine.erase("kernels");
  old.source = "results/prototype__simtex-mini__seed1.json";
  EXPECT_NE(message_of([&] { reference_values_of({old}, 2.0); })
                .find("results/prototype__simtex-mini__seed1.json: machine.kernels '', expected the kernels"),
            std::string::npos);
  // A comma would split the field in the file.
  old.machine["kernels"] = "aten=AVX2,openblas=Zen";
  EXPECT_NE(message_of([&] { reference_values_of({old}, 2.0); }).find("machine.kernels 'aten=AVX2,openblas=Zen'"),
            std::string::npos);
}

TEST(ReferenceNumbers, BadFilesNameFileLineAndWhatWasExpected) {
  TemporaryDirectory directory;
  const auto path = directory.path() / "reference.csv";
  const std::string header = "method,dataset,profile,seed,threads,metric,expected,tolerance\n";
  std::ofstream(path) << header << "prototype,simtex-mini,smoke,1,2,AA,50\n";
  EXPECT_NE(message_of([&] { load_reference_csv(path); }).find("reference.csv:2: 7 fields, expected 8"),
            std::string::npos);
  std::ofstream(path) << "# comment\n" << header << "prototype,simtex-mini,smoke,1,2,AA,nan,2\n";
  EXPECT_NE(message_of([&] { load_reference_csv(path); }).find("reference.csv:3 expected: 'nan' is not a finite number"),
            std::string::npos);
  std::ofstream(path) << "method,value\n";
  EXPECT_NE(message_of([&] { load_reference_csv(path); }).find("reference.csv:1: header 'method,value'"),
            std::string::npos);
  EXPECT_NE(message_of([&] { load_reference_csv(directory.path() / "absent.csv"); })
                .find("absent.csv: no such file, expected a reference CSV"),
            std::string::npos);
  // Saved by a spreadsheet (byte-order mark, CRLF) it reads as written; a header that differs by
  // an invisible byte shows the byte.
  std::ofstream(path) << "\xEF\xBB\xBF" << "method,dataset,profile,seed,threads,metric,expected,tolerance\r\n"
                      << "prototype,simtex-mini,smoke,1,2,AA,50,2\r\n";
  const auto values = load_reference_csv(path);
  ASSERT_EQ(values.size(), 1u);
  EXPECT_EQ(values[0].tolerance, 2);
  // Values no run can reach, and a tolerance that would pass any drift, are the file's typos.
  for (const auto& [row, reason] : std::vector<std::pair<std::string, std::string>>{
           {"AA,150,2", "reference.csv:2: AA of 150, expected a value in [0, 100]"},
           {"PD,-101,2", "reference.csv:2: PD of -101, expected a value in [-100, 100]"},
           {"ADR,101,2", "reference.csv:2: ADR of 101, expected a value"},
           {"acc_0,50,1e30", "reference.csv:2: tolerance 1e30, expected percentage points in [0, 100]"},
           {"acc_0,50,-1", "reference.csv:2: tolerance -1, expected percentage points in [0, 100]"}}) {
    std::ofstream(path) << header << "prototype,simtex-mini,smoke,1,2," << row << "\n";
    EXPECT_NE(message_of([&] { load_reference_csv(path); }).find(reason), std::string::npos)
        << message_of([&] { load_reference_csv(path); });
  }
  std::ofstream(path) << header << "prototype,simtex-mini,smoke,1,2,PD,-40,100\n";  // a model that gained
  EXPECT_EQ(load_reference_csv(path).at(0).expected, -40);
  std::ofstream(path) << "method,dataset,profile,seed,threads,metric,expected,tolerance\x7f\n";
  EXPECT_NE(message_of([&] { load_reference_csv(path); })
                .find("reference.csv:1: header 'method,dataset,profile,seed,threads,metric,expected,tolerance\\x7f', "
                      "expected 'method,"),
            std::string::npos);
}

// Found by fuzzing: a seed of 2e30 was converted to an integer with undefined behaviour.
TEST(ReferenceNumbers, SeedAndThreadsAreWholeNumbersInTheirRange) {
  TemporaryDirectory directory;
  const auto path = directory.path() / "reference.csv";
  const std::string header = "method,dataset,profile,seed,threads,metric,expected,tolerance\n";
  std::ofstream(path) << header << "prototype,simtex-mini,smoke,2e30,2,AA,50,2\n";
  EXPECT_NE(message_of([&] { load_reference_csv(path); })
                .find("reference.csv:2 seed: '2e30', expected a whole number from 0 to 18446744073709551615"),
            std::string::npos);
  for (const char* threads : {"-2", "0", "1.5", "3000000000"}) {
    std::ofstream(path) << header << "prototype,simtex-mini,smoke,1," << threads << ",AA,50,2\n";
    const std::string expected =
        fmt::format("reference.csv:2 threads: '{}', expected a whole number from 1 to 2147483647", threads);
    EXPECT_NE(message_of([&] { load_reference_csv(path); }).find(expected), std::string::npos);
  }
  // Seeds beyond 2^53 are read exactly, as --seeds takes them.
  std::ofstream(path) << header << "prototype,simtex-mini,smoke,999999999999999999,2,AA,50,2\n";
  EXPECT_EQ(load_reference_csv(path).at(0).seed, 999999999999999999u);
}

}  // namespace
}  // namespace fscil
