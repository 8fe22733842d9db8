#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "datasets/readers/signal_data.h"

namespace fscil {

// A comma-separated file with a header row, as text, read by the one CSV reader (core/csv_text.h):
// every field trimmed, quotes around a field removed. Rows keep their 1-based line numbers for
// error messages.
struct TextTable {
  std::filesystem::path path;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::vector<int> line_of_row;

  // Index of a header column; throws DatasetError naming the file and the columns it has.
  std::size_t column(const std::string& name) const;
  bool has_column(const std::string& name) const;
};

// The largest text file a reader takes (a recording, a manifest): past it the file is refused
// before it is read, so a job with a memory limit fails with a line, not an out-of-memory kill.
constexpr std::uintmax_t kMaxTextFileBytes = std::uintmax_t{1} << 30;

// Reads a CSV with a header. Throws DatasetError (file and line) when the file is missing,
// empty, or a row has a different number of fields than the header.
TextTable read_text_table(const std::filesystem::path& path);

// One ASCII number per line (LMT108's TXT files). Blank lines are skipped.
SignalData read_single_column(const std::filesystem::path& path);

// A CSV whose header names its columns and whose rows are samples; returns the named
// channels in the order asked, streamed (the peak is about the samples as floats, not the text).
// Throws DatasetError for a missing channel column, a wrong field count, a non-numeric value or a
// NaN/Inf, naming file, line and column.
SignalData read_signal_csv(const std::filesystem::path& path, const std::vector<std::string>& channels);

// Parses a whole field as a finite float; `where` names file, line and column for the error.
float parse_finite_float(const std::string& field, const std::string& where);

}  // namespace fscil
