#include "datasets/readers/text_table.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <vector>

#include "core/csv_text.h"
#include "core/error.h"
#include "datasets/readers/regular_file.h"
#include "core/shown_text.h"
#include "core/number_text.h"

namespace fscil {

namespace {

std::ifstream open_or_throw(const std::filesystem::path& path) {
  if (!names_a_regular_file(path)) throw DatasetError(fmt::format("{}: {}", path.string(), why_not_a_regular_file(path)));
  std::error_code unknown;
  const auto bytes = std::filesystem::file_size(path, unknown);
  if (!unknown && bytes > kMaxTextFileBytes) {
    throw DatasetError(fmt::format("{}: {} bytes, expected a text file of at most {} bytes (1 GiB: about an hour of "
                                   "three channels at 10 kHz)", path.string(), bytes, kMaxTextFileBytes));
  }
  std::ifstream in(path);
  if (!in) throw DatasetError(fmt::format("{}: cannot be opened for reading", path.string()));
  return in;
}

// A row of a table is a few fields; a file without line breaks is no table, and reading it as one
// line took 3.6 times its size before any check.
constexpr std::streamsize kMaxLineBytes = std::streamsize{1} << 20;

// The next line, without the byte-order mark a spreadsheet may put before the first one; throws
// on a line past kMaxLineBytes.
bool next_line(std::ifstream& in, std::string& line, int& line_number, const std::filesystem::path& path) {
  thread_local std::vector<char> buffer(static_cast<std::size_t>(kMaxLineBytes) + 1);
  in.getline(buffer.data(), kMaxLineBytes + 1);
  const std::streamsize read = in.gcount();
  if (in.eof() && read == 0) return false;
  ++line_number;
  if (in.fail() && !in.eof()) {
    throw DatasetError(fmt::format("{}:{}: a line longer than {} MiB, expected the rows of a text table (one sample, "
                                   "or one recording, a line)", path.string(), line_number, kMaxLineBytes >> 20));
  }
  const bool ended_by_newline = !in.eof();
  line.assign(buffer.data(), static_cast<std::size_t>(ended_by_newline ? read - 1 : read));
  if (line_number == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);
  return true;
}

bool blank(const std::string& line) { return line.find_first_not_of(" \t\r\n") == std::string::npos; }

// Blank lines of a recording: at its end they are nothing; between samples they would be a
// sample lost without a word (every later one shifted in time), so they are refused.
class BlankLines {
 public:
  explicit BlankLines(const std::filesystem::path& path) : path_(path) {}
  // True when `line` is blank (skip it); throws when a sample follows a blank line.
  bool skip(const std::string& line, int line_number, bool samples_started) {
    if (blank(line)) {
      if (samples_started && first_blank_ == 0) first_blank_ = line_number;
      return true;
    }
    if (first_blank_ != 0) {
      throw DatasetError(fmt::format("{}:{}: a blank line between samples (line {} follows it), expected one sample "
                                     "per line to the end", path_.string(), first_blank_, line_number));
    }
    return false;
  }

 private:
  const std::filesystem::path& path_;
  int first_blank_ = 0;
};

// A column named twice leaves which one is read to the reader's whim: refused.
void require_distinct_columns(const std::vector<std::string>& header, const std::filesystem::path& path, int line) {
  for (std::size_t c = 1; c < header.size(); ++c) {
    if (std::find(header.begin(), header.begin() + static_cast<std::ptrdiff_t>(c), header[c]) !=
        header.begin() + static_cast<std::ptrdiff_t>(c)) {
      throw DatasetError(fmt::format("{}:{}: column '{}' appears twice in the header, expected distinct names",
                                     path.string(), line, shown_text(header[c])));
    }
  }
}

}  // namespace

std::size_t TextTable::column(const std::string& name) const {
  for (std::size_t c = 0; c < header.size(); ++c) {
    if (header[c] == name) return c;
  }
  throw DatasetError(fmt::format("{}: no column '{}' in the header (it has {})", path.string(), name,
                                 shown_text(fmt::format("{}", fmt::join(header, ",")))));
}

bool TextTable::has_column(const std::string& name) const {
  for (const auto& column_name : header) {
    if (column_name == name) return true;
  }
  return false;
}

TextTable read_text_table(const std::filesystem::path& path) {
  std::ifstream in = open_or_throw(path);
  TextTable table;
  table.path = path;
  std::string line;
  int line_number = 0;
  while (next_line(in, line, line_number, path)) {
    if (blank(line)) continue;
    auto fields = csv_fields(line);
    if (table.header.empty()) {
      require_distinct_columns(fields, path, line_number);
      table.header = std::move(fields);
      continue;
    }
    if (fields.size() != table.header.size()) {
      throw DatasetError(fmt::format("{}:{}: {} fields, expected {} like the header ({})", path.string(),
                                     line_number, fields.size(), table.header.size(),
                                     shown_text(fmt::format("{}", fmt::join(table.header, ",")))));
    }
    table.rows.push_back(std::move(fields));
    table.line_of_row.push_back(line_number);
  }
  if (table.header.empty()) throw DatasetError(fmt::format("{}: empty file, expected a header row", path.string()));
  return table;
}

float parse_finite_float(const std::string& field, const std::string& where) {
  const auto value = parse_number<float>(field);
  if (!value && parse_number<double>(field)) {
    throw DatasetError(fmt::format("{}: {} is outside the range of a 32-bit float sample (magnitudes from about "
                                   "1.2e-38 to 3.4e38, or 0)", where, shown_text(field)));
  }
  if (!value) throw DatasetError(fmt::format("{}: '{}' is not a number", where, shown_text(field)));
  if (!std::isfinite(*value)) throw DatasetError(fmt::format("{}: {} found, expected a finite number", where, field));
  return *value;
}

SignalData read_single_column(const std::filesystem::path& path) {
  std::ifstream in = open_or_throw(path);
  SignalData signal;
  signal.channels = 1;
  std::string line;
  int line_number = 0;
  BlankLines blanks(path);
  while (next_line(in, line, line_number, path)) {
    if (blanks.skip(line, line_number, !signal.values.empty())) continue;
    const std::string field = trimmed(line);
    if (field.find_first_of(",; \t") != std::string::npos) {
      throw DatasetError(fmt::format("{}:{}: '{}' holds several values, expected one number per line", path.string(),
                                     line_number, shown_text(field)));
    }
    signal.values.push_back(parse_finite_float(field, fmt::format("{}:{}", path.string(), line_number)));
  }
  if (signal.values.empty()) throw DatasetError(fmt::format("{}: empty file, expected one number per line", path.string()));
  signal.length = static_cast<std::int64_t>(signal.values.size());
  return signal;
}

SignalData read_signal_csv(const std::filesystem::path& path, const std::vector<std::string>& channels) {
  // Streamed line by line into floats: a table of text fields first took four times the file.
  std::ifstream in = open_or_throw(path);
  TextTable header_only;
  header_only.path = path;
  std::vector<std::size_t> columns;
  std::vector<std::vector<float>> samples(channels.size());
  std::string line;
  int line_number = 0;
  BlankLines blanks(path);
  while (next_line(in, line, line_number, path)) {
    if (blanks.skip(line, line_number, !header_only.header.empty())) continue;
    const auto fields = csv_fields(line);
    if (header_only.header.empty()) {
      require_distinct_columns(fields, path, line_number);
      header_only.header = fields;
      for (const auto& name : channels) columns.push_back(header_only.column(name));
      continue;
    }
    if (fields.size() != header_only.header.size()) {
      throw DatasetError(fmt::format("{}:{}: {} fields, expected {} like the header ({})", path.string(), line_number,
                                     fields.size(), header_only.header.size(),
                                     shown_text(fmt::format("{}", fmt::join(header_only.header, ",")))));
    }
    for (std::size_t k = 0; k < columns.size(); ++k) {
      const std::string& field = fields[columns[k]];
      const auto value = parse_number<float>(field);
      if (!value || !std::isfinite(*value)) {  // says what is wrong, and where
        parse_finite_float(field, fmt::format("{}:{} column {}", path.string(), line_number, channels[k]));
      }
      samples[k].push_back(*value);
    }
  }
  if (header_only.header.empty()) throw DatasetError(fmt::format("{}: empty file, expected a header row", path.string()));
  if (samples.empty() || samples.front().empty()) {
    throw DatasetError(fmt::format("{}: a header but no samples", path.string()));
  }
  SignalData signal;
  signal.channels = static_cast<std::int64_t>(channels.size());
  signal.length = static_cast<std::int64_t>(samples.front().size());
  signal.values.reserve(static_cast<std::size_t>(signal.channels * signal.length));
  for (auto& channel : samples) {
    signal.values.insert(signal.values.end(), channel.begin(), channel.end());
    std::vector<float>().swap(channel);
  }
  return signal;
}

}  // namespace fscil
