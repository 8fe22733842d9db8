#pragma once
#include <string>

namespace fscil {

// How the stored reference numbers are regenerated (README, reports/reference/).
inline constexpr const char* kRegenerateReferences = "bash tools/reference_protocol.sh regenerate";

// Writes the reference file of every run below `results`, each value with `tolerance`.
void write_reference(const std::string& results, const std::string& out, double tolerance);

// Compares the runs below `results` with `reference`; prints one line per failure and a summary.
// Returns the exit status: 0 when every value is within tolerance, 1 otherwise.
int check_reference(const std::string& results, const std::string& reference);

}  // namespace fscil
