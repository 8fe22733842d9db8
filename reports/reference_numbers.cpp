#include "reports/reference_numbers.h"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <set>

#include "metrics/fscil_metrics.h"
#include "core/shown_text.h"
#include "reports/csv_fields.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/text_file.h"
#include "core/number_text.h"

namespace fscil {

namespace {

constexpr const char* kHeader = "method,dataset,profile,seed,threads,kernels,metric,expected,tolerance";
constexpr std::size_t kFields = 9;
constexpr std::size_t kKernelsColumn = 5;
// Files written before the kernels were recorded: read with empty kernels.
constexpr const char* kHeaderWithoutKernels = "method,dataset,profile,seed,threads,metric,expected,tolerance";

std::string kernels_of(const RunRecord& record) {
  const auto found = record.machine.find("kernels");
  return found != record.machine.end() ? found->second : std::string();
}

// A whole number from `low` to T's largest filling the field: read as a double, a seed above 2^53
// would round and a value beyond T's range could not be converted at all.
template <typename T>
T whole_number(const std::string& text, T low, const std::string& where) {
  const auto value = parse_number<T>(text);
  if (!value || *value < low) {
    throw ReportError(fmt::format("{}: '{}', expected a whole number from {} to {}", where, shown_text(text), low,
                                  std::numeric_limits<T>::max()));
  }
  return *value;
}

// metric name -> value of one run.
std::vector<std::pair<std::string, double>> metrics_of(const RunRecord& record) {
  const auto accuracies = record.session_accuracies();
  std::vector<std::pair<std::string, double>> metrics;
  for (std::size_t s = 0; s < accuracies.size(); ++s) metrics.emplace_back(fmt::format("acc_{}", s), accuracies[s]);
  const FscilSummary summary = summarize_sessions(accuracies);
  metrics.emplace_back("AA", summary.average_accuracy);
  metrics.emplace_back("PD", summary.performance_drop);
  metrics.emplace_back("ADR", summary.average_drop_rate);
  return metrics;
}

// What metrics_of() names: acc_0, acc_1, ... (no sign, no leading zero), AA, PD, ADR.
bool is_metric_name(const std::string& metric) {
  if (metric == "AA" || metric == "PD" || metric == "ADR") return true;
  const std::string digits = metric.rfind("acc_", 0) == 0 ? metric.substr(4) : std::string();
  return !digits.empty() && digits.size() <= 4 && digits.find_first_not_of("0123456789") == std::string::npos &&
         (digits == "0" || digits[0] != '0');
}

// The values `metric` can take, in percentage points: an accuracy and AA from 0 to 100, PD
// = Acc_0 - Acc_S from -100 to 100, ADR (each session's drop over its accuracy) at most 100.
ValidRange range_of(const std::string& metric) {
  if (metric == "PD") return ValidRange::between(-100, 100);
  if (metric == "ADR") return ValidRange::at_most(100);
  return ValidRange::between(0, 100);
}

}  // namespace

std::vector<ReferenceValue> reference_values_of(const std::vector<RunRecord>& records, double tolerance) {
  std::vector<ReferenceValue> values;
  for (const auto& record : records) {
    if (record.evaluated_on != "test") {
      throw ReportError(fmt::format("{} on {} seed {}: scored on the {} split; reference numbers are test-split numbers",
                                    record.method, record.dataset, record.seed, record.evaluated_on));
    }
    if (precision_of(record) != "fp32") {
      throw ReportError(fmt::format("{} on {} seed {}: made in {}; reference numbers are fp32 runs' numbers",
                                    record.method, record.dataset, record.seed, precision_of(record)));
    }
    const std::string kernels = kernels_of(record);
    const bool one_field = std::none_of(kernels.begin(), kernels.end(), [](char c) { return c == ',' || c < ' '; });
    if (kernels.empty() || !one_field) {
      throw ReportError(fmt::format("{}: machine.kernels '{}', expected the kernels the run was made with, without "
                                    "commas (result files written before they were recorded cannot make references)",
                                    record.source, shown_text(kernels)));
    }
    for (const auto& [metric, value] : metrics_of(record)) {
      values.push_back({record.method, record.dataset, record.profile, record.seed, record.threads, kernels, metric,
                        value, tolerance});
    }
  }
  return values;
}

namespace {
constexpr const char* kFirstLine = "# fscil-bench reference numbers: session accuracies and AA/PD/ADR in percentage points.";
}  // namespace

bool holds_reference_csv(const std::filesystem::path& path) {
  std::ifstream file(path);
  std::string first;
  return std::getline(file, first) && first == kFirstLine;
}

std::string render_reference_csv(const std::vector<ReferenceValue>& values, const std::string& regenerate_command) {
  std::string out = fmt::format(
      "{}\n"
      "# A run passes when every value is within expected +- tolerance (two-sided).\n"
      "# Regenerate (never in CI): {}\n{}\n",
      kFirstLine, regenerate_command, kHeader);
  for (const auto& v : values) {
    out += fmt::format("{},{},{},{},{},{},{},{:.4f},{:.4f}\n", v.method, v.dataset, v.profile, v.seed, v.threads,
                       v.kernels, v.metric, v.expected, v.tolerance);
  }
  return out;
}

std::vector<ReferenceValue> load_reference_csv(const std::filesystem::path& path) {
  if (const std::string why = why_not_a_regular_file(path); !why.empty()) {
    throw ReportError(fmt::format("{}: {}, expected a reference CSV", path.string(), why));
  }
  std::vector<ReferenceValue> values;
  std::map<std::string, int> line_of_value;  // a value given twice would pass on one line and fail on the other
  bool header_seen = false;
  bool with_kernels = true;
  int line_number = 0;
  never_replace(path);
  for (const std::string& line : csv_lines(read_text_file(path))) {
    ++line_number;
    if (line.empty() || line[0] == '#') continue;
    const std::string where = fmt::format("{}:{}", path.string(), line_number);
    if (!header_seen) {
      if (line != kHeader && line != kHeaderWithoutKernels) {
        throw ReportError(fmt::format("{}: header '{}', expected '{}' (or, from before kernels were recorded, '{}')",
                                      where, shown_text(line), kHeader, kHeaderWithoutKernels));
      }
      header_seen = true;
      with_kernels = line == kHeader;
      continue;
    }
    auto fields = csv_fields(line);
    const std::size_t fields_expected = with_kernels ? kFields : kFields - 1;
    if (fields.size() != fields_expected) {
      throw ReportError(fmt::format("{}: {} fields, expected {} ({})", where, fields.size(), fields_expected,
                                    with_kernels ? kHeader : kHeaderWithoutKernels));
    }
    if (!with_kernels) fields.insert(fields.begin() + kKernelsColumn, std::string());
    ReferenceValue value{fields[0], fields[1], fields[2], 0, 0, fields[5], fields[6], 0, 0};
    value.seed = whole_number<std::uint64_t>(fields[3], 0, where + " seed");
    value.threads = whole_number<int>(fields[4], 1, where + " threads");
    value.expected = finite_number(fields[7], where + " expected");
    value.tolerance = finite_number(fields[8], where + " tolerance");
    if (!reference_tolerance_range().contains(value.tolerance)) {
      throw ReportError(fmt::format("{}: tolerance {}, expected percentage points {} (100 passes any accuracy)", where,
                                    fields[8], reference_tolerance_range().describe()));
    }
    if (!is_metric_name(value.metric)) {
      throw ReportError(fmt::format("{}: metric '{}', expected acc_0, acc_1, ... (a session's accuracy), AA, PD or ADR",
                                    where, shown_text(value.metric)));
    }
    if (const ValidRange range = range_of(value.metric); !range.contains(value.expected)) {
      throw ReportError(fmt::format("{}: {} of {}, expected a value {} (percentage points)", where, value.metric,
                                    fields[7], range.describe()));
    }
    const std::string key = fmt::format("{} on {} seed {} ({} threads, {}) {}", value.method, value.dataset, value.seed,
                                        value.threads, value.kernels.empty() ? "any kernels" : value.kernels, value.metric);
    if (const auto [earlier, fresh] = line_of_value.emplace(key, line_number); !fresh) {
      throw ReportError(fmt::format("{}: {} given again (line {} gives it), expected one value of each", where,
                                    shown_text(key), earlier->second));
    }
    values.push_back(std::move(value));
  }
  if (values.empty()) throw ReportError(fmt::format("{}: no reference values", path.string()));
  return values;
}

ReferenceCheck check_against_reference(const std::vector<RunRecord>& records,
                                       const std::vector<ReferenceValue>& reference) {
  std::map<std::tuple<std::string, std::string, std::uint64_t>, const RunRecord*> runs;
  for (const auto& record : records) runs[{record.method, record.dataset, record.seed}] = &record;
  ReferenceCheck check;
  std::map<const RunRecord*, std::map<std::string, double>> metrics;
  std::set<std::string> unusable_runs;  // reported once, not once per value
  // One file may hold values of several kernels: a run is compared with those of its own.
  std::set<std::tuple<std::string, std::string, std::uint64_t, std::string>> stored_kernels;
  for (const auto& value : reference) stored_kernels.insert({value.method, value.dataset, value.seed, value.kernels});
  for (const auto& expected : reference) {
    const auto found = runs.find({expected.method, expected.dataset, expected.seed});
    const std::string run_name = fmt::format("{} on {} seed {}", expected.method, expected.dataset, expected.seed);
    if (unusable_runs.count(run_name) > 0) continue;
    if (found == runs.end()) {
      check.failures.push_back(fmt::format("{}: no result file for this run", run_name));
      unusable_runs.insert(run_name);
      continue;
    }
    const RunRecord& run = *found->second;
    if (run.evaluated_on != "test") {
      check.failures.push_back(fmt::format("{}: scored on the {} split; reference numbers are test-split numbers",
                                           run_name, run.evaluated_on));
      unusable_runs.insert(run_name);
      continue;
    }
    if (precision_of(run) != "fp32") {
      check.failures.push_back(fmt::format("{}: made in {}; reference numbers are fp32 runs' numbers", run_name,
                                           precision_of(run)));
      unusable_runs.insert(run_name);
      continue;
    }
    if (run.profile != expected.profile || run.threads != expected.threads) {
      check.failures.push_back(fmt::format("{}: ran with profile {} and {} threads, the reference with {} and {}",
                                           run_name, run.profile, run.threads, expected.profile, expected.threads));
      unusable_runs.insert(run_name);
      continue;
    }
    const std::string kernels = kernels_of(run);
    if (!expected.kernels.empty() && kernels != expected.kernels) {
      if (stored_kernels.count({expected.method, expected.dataset, expected.seed, kernels}) > 0) continue;
      check.failures.push_back(fmt::format(
          "{}: ran on kernels {}, the reference holds values of kernels {}; values of other kernels are not "
          "compared (README, Reference numbers)",
          run_name, kernels.empty() ? "unrecorded" : kernels, expected.kernels));
      unusable_runs.insert(run_name);
      continue;
    }
    auto& values = metrics[&run];
    if (values.empty()) {
      for (const auto& [metric, value] : metrics_of(run)) values[metric] = value;
    }
    ++check.values_checked;
    const auto got = values.find(expected.metric);
    if (got == values.end()) {
      check.failures.push_back(fmt::format("{} {}: expected {:.2f}, the run has no such value", run_name,
                                           expected.metric, expected.expected));
    } else if (std::abs(got->second - expected.expected) > expected.tolerance + 1e-9) {
      check.failures.push_back(fmt::format("{} {}: expected {:.2f} +- {:.2f}, got {:.2f} ({:+.2f})", run_name,
                                           expected.metric, expected.expected, expected.tolerance, got->second,
                                           got->second - expected.expected));
    }
  }
  return check;
}

}  // namespace fscil
