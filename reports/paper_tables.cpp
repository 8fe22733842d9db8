#include "reports/paper_tables.h"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <sstream>

#include "reports/atomic_file.h"
#include "reports/report_error.h"

namespace fscil {

namespace {

const char* const kHeader = "table,dataset,method,venue,session_acc,PD,AA,ADR";

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::stringstream stream(text);
  std::string part;
  while (std::getline(stream, part, separator)) parts.push_back(part);
  if (!text.empty() && text.back() == separator) parts.emplace_back();
  return parts;
}

double number(const std::string& text, const std::string& where) {
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(value)) {
    throw ReportError(fmt::format("{}: '{}' is not a finite number", where, text));
  }
  return value;
}

}  // namespace

std::vector<PaperRow> load_paper_tables(const std::filesystem::path& path) {
  std::stringstream lines(read_text_file(path));
  std::string line;
  if (!std::getline(lines, line) || line != kHeader) {
    throw ReportError(fmt::format("{}:1: header must be '{}'", path.string(), kHeader));
  }
  std::vector<PaperRow> rows;
  for (int number_of_line = 2; std::getline(lines, line); ++number_of_line) {
    if (line.empty()) continue;
    const std::string where = fmt::format("{}:{}", path.string(), number_of_line);
    const auto fields = split(line, ',');
    if (fields.size() != 8) throw ReportError(fmt::format("{}: {} fields, expected 8", where, fields.size()));
    PaperRow row{fields[0], fields[1], fields[2], fields[3], {}, 0, 0, 0};
    std::stringstream accuracies(fields[4]);
    std::string value;
    while (accuracies >> value) row.session_accuracy.push_back(number(value, where + " session_acc"));
    if (row.session_accuracy.size() < 2) throw ReportError(fmt::format("{}: session_acc needs at least 2 values", where));
    row.performance_drop = number(fields[5], where + " PD");
    row.average_accuracy = number(fields[6], where + " AA");
    row.average_drop_rate = number(fields[7], where + " ADR");
    rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace fscil
