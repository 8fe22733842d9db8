#include "tools/fscil-bench/commands/reference_command.h"

#include <fmt/format.h>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/atomic_file.h"
#include "reports/reference_numbers.h"
#include "core/error.h"
#include "core/shown_text.h"
#include "reports/run_record.h"
#include "reports/summary_table.h"
#include "tools/fscil-bench/cells/bench_cells.h"
#include "tools/fscil-bench/cells/command_arguments.h"
#include "tools/fscil-bench/options/data_folder.h"

namespace fscil {

namespace {

// How `reference` is made again: the repository's own files by their script, a user's by the
// command that wrote it (its tolerance where known).
std::string regenerate_command(const std::string& results, const std::string& reference,
                               std::optional<double> tolerance = std::nullopt) {
  std::error_code error;
  // The folder itself: weakly_canonical drops a trailing separator, so the folder of "dir/" would
  // read as dir's parent and the repository's files would be told a user's command.
  const auto own = std::filesystem::weakly_canonical(reference_file("").parent_path(), error);
  const auto file = std::filesystem::weakly_canonical(reference, error);
  if (!error && file.parent_path() == own) return kRegenerateReferences;
  // Printed for pasting into a shell, and written as the CSV's one comment line.
  for (const std::string* path : {&results, &reference}) {
    if (path->find_first_of("\n\r") != std::string::npos) {
      throw ReportError(fmt::format("{}: a line break in the path; the reference CSV's one-line 'Regenerate' "
                                    "comment cannot name it: rename the folder",
                                    shown_text(*path)));
    }
  }
  std::vector<std::string> words = {"fscil-bench", "reference", "--results", results, "--out", reference};
  if (tolerance) words.insert(words.end(), {"--tolerance", fmt::format("{}", *tolerance)});
  return shell_command(words);
}

}  // namespace

void write_reference(const std::string& results, const std::string& out, double tolerance) {
  if (!reference_tolerance_range().contains(tolerance)) {
    throw ReportError(fmt::format("--tolerance {}: expected percentage points {}", tolerance,
                                  reference_tolerance_range().describe()));
  }
  tolerance += 0.0;  // -0 is 0: written as 0.0000, not -0.0000
  const auto records = load_command_records(results, "", {});
  require_replaceable(out);
  if (std::filesystem::exists(out) && !holds_reference_csv(out)) {
    throw ReportError(fmt::format("{}: would be replaced, and it is not a reference CSV (fscil-bench writes one "
                                  "beginning '# fscil-bench reference numbers'); move it away or choose another --out",
                                  shown_text(out)));
  }
  if (records.empty()) throw ReportError(fmt::format("{}: no result files to take references from", results));
  const auto values = reference_values_of(records, tolerance);
  write_file_atomically(out, render_reference_csv(values, regenerate_command(results, out, tolerance)));
  fmt::print("{} reference values of {} runs written to {}\n", values.size(), records.size(), out);
}

int check_reference(const std::string& results, const std::string& reference) {
  const auto expected = load_reference_csv(reference);
  const auto records = load_command_records(results, "", {});
  fmt::print(stderr, "{}", unfinished_warning(records));
  const ReferenceCheck check = check_against_reference(records, expected);
  for (const auto& failure : check.failures) fmt::print("FAIL {}\n", failure);
  if (check.failures.empty()) {
    fmt::print("all {} reference values of {} hold in {}\n", check.values_checked, reference, results);
    return 0;
  }
  fmt::print("{} failures, {} of {} reference values compared; if a changed value is intended, regenerate with: {}\n",
             check.failures.size(), check.values_checked, expected.size(),
             regenerate_command(results, reference));
  return 1;
}

}  // namespace fscil
