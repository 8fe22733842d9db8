#pragma once
#include <filesystem>
#include <string>
#include <vector>

namespace fscil {

// One row of the paper's results and ablation tables, as printed.
struct PaperRow {
  std::string table;
  std::string dataset;
  std::string method;
  std::string venue;
  std::vector<double> session_accuracy;
  double performance_drop = 0;
  double average_accuracy = 0;
  double average_drop_rate = 0;
};

// Reads reports/reference/paper_tables.csv (table,dataset,method,venue,session_acc,PD,AA,ADR;
// session accuracies space-separated). Throws ReportError naming the file, line and field.
std::vector<PaperRow> load_paper_tables(const std::filesystem::path& path);

}  // namespace fscil
