#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/valid_range.h"
#include "reports/run_record.h"

namespace fscil {

// One expected value of one run: a session accuracy (acc_0, acc_1, ...) or AA, PD, ADR, in
// percentage points, with the two-sided tolerance it must stay within (a gain is as suspicious
// as a loss).
struct ReferenceValue {
  std::string method;
  std::string dataset;
  std::string profile;
  std::uint64_t seed = 0;
  int threads = 0;
  // The kernels the value was made with (numeric_kernels(), tools/fscil-bench/options/machine_info.h); empty in
  // files written before they were recorded, which compare with runs on any kernels.
  std::string kernels;
  std::string metric;
  double expected = 0;
  double tolerance = 0;
};

// The tolerances a reference takes, in percentage points: 100 already passes any accuracy.
inline ValidRange reference_tolerance_range() { return ValidRange::between(0, 100); }

// Every value of every run in `records`, each with `tolerance`.
std::vector<ReferenceValue> reference_values_of(const std::vector<RunRecord>& records, double tolerance);

// CSV with a comment header saying how it was made and how to regenerate it.
std::string render_reference_csv(const std::vector<ReferenceValue>& values, const std::string& regenerate_command);
// Whether `path` begins as render_reference_csv writes: a reference CSV that `reference` may replace.
bool holds_reference_csv(const std::filesystem::path& path);
// Throws ReportError naming the file, line and field.
std::vector<ReferenceValue> load_reference_csv(const std::filesystem::path& path);

// What a comparison of result files with references found: one line per value out of
// tolerance, per run missing and per run made with other threads, profile or kernels (whose
// values are not compared: rounding differs, and a short run amplifies it). Empty when
// everything agrees.
struct ReferenceCheck {
  std::vector<std::string> failures;
  std::size_t values_checked = 0;
};
ReferenceCheck check_against_reference(const std::vector<RunRecord>& records,
                                       const std::vector<ReferenceValue>& reference);

}  // namespace fscil
