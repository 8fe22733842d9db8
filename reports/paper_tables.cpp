#include "reports/paper_tables.h"

#include <fmt/format.h>

#include <sstream>

#include "core/text_file.h"
#include "reports/csv_fields.h"
#include "core/error.h"

namespace fscil {

namespace {

const char* const kPaperTablesHeader = "table,dataset,method,venue,session_acc,PD,AA,ADR";

}  // namespace

std::vector<PaperRow> load_paper_tables(const std::filesystem::path& path) {
  const std::vector<std::string> lines = csv_lines(read_text_file(path));
  if (lines.empty() || lines[0] != kPaperTablesHeader) {
    throw ReportError(fmt::format("{}:1: header must be '{}'", path.string(), kPaperTablesHeader));
  }
  std::vector<PaperRow> rows;
  for (std::size_t number = 1; number < lines.size(); ++number) {
    const std::string& line = lines[number];
    if (line.empty()) continue;
    const std::string where = fmt::format("{}:{}", path.string(), number + 1);
    const auto fields = csv_fields(line);
    if (fields.size() != 8) throw ReportError(fmt::format("{}: {} fields, expected 8", where, fields.size()));
    PaperRow row{fields[0], fields[1], fields[2], fields[3], {}, 0, 0, 0};
    std::stringstream accuracies(fields[4]);
    std::string value;
    while (accuracies >> value) row.session_accuracy.push_back(finite_number(value, where + " session_acc"));
    if (row.session_accuracy.size() < 2) throw ReportError(fmt::format("{}: session_acc needs at least 2 values", where));
    row.performance_drop = finite_number(fields[5], where + " PD");
    row.average_accuracy = finite_number(fields[6], where + " AA");
    row.average_drop_rate = finite_number(fields[7], where + " ADR");
    rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace fscil
