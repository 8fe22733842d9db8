#pragma once
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "reports/cost_table.h"
#include "reports/summary_table.h"

namespace fscil {

// One row of the paper's analysis tables (reports/reference/paper_analyses.csv): a setting of one
// table on one dataset, as KEY=VALUE[+KEY=VALUE] like a sweep cell, with the numbers printed
// (NaN where the table has none).
struct PaperSetting {
  std::string table, dataset, setting;
  double acc0 = 0, pd = 0, aa = 0, adr = 0, update_seconds = 0;
};

// Throws ReportError naming the file, line and field.
std::vector<PaperSetting> load_paper_analyses(const std::filesystem::path& path);

// One of the paper's tables over the settings of a sweep: a row per sweep cell of `method` on
// `dataset` (Acc0, PD, AA, ADR; with `update_time` the mean time per incremental session), the
// paper's numbers for the same setting beside ours where `paper` has them and ours were scored on
// the test split.
struct SettingTable {
  std::string name;     // the reproduction, e.g. "lambda"
  std::string caption;  // the paper's caption
  std::string method, dataset;
  bool update_time = false;
  // How the LaTeX table names a sweep key, as the paper's table does (pspc_probes as
  // "$N_{\mathrm{ps}}$"); a key without one is printed as it is typed.
  std::vector<std::pair<std::string, std::string>> latex_keys;
  struct Row {
    std::string setting;  // grid_cell_name of the cell
    GridCell cell;
    std::string seeds;
    double acc0 = 0, pd = 0, aa = 0, adr = 0, update_seconds = 0;
    bool selected_on_test = false;
    std::optional<PaperSetting> paper;
  };
  std::vector<Row> rows;
};

SettingTable make_setting_table(const std::string& name, const std::string& caption, const std::string& method,
                                const std::string& dataset, const SummaryTable& table,
                                const std::vector<CostRow>& costs, const std::vector<PaperSetting>& paper,
                                bool update_time,
                                std::vector<std::pair<std::string, std::string>> latex_keys = {});

// CSV (ours and paper's columns), Markdown and LaTeX (the paper's layout, best of ours in bold).
std::string render_setting_csv(const SettingTable& table);
std::string render_setting_markdown(const SettingTable& table);
std::string render_setting_latex(const SettingTable& table);

}  // namespace fscil
