#include "reports/cost_table.h"

#include <fmt/format.h>

#include <algorithm>

#include "reports/latex_text.h"

namespace fscil {

namespace {

constexpr double kMebibyte = 1024.0 * 1024.0;

// Index of the row of (method, dataset, cell), appended when new.
std::size_t row_index(std::vector<CostRow>& rows, const RunRecord& record) {
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (rows[i].method == record.method && rows[i].dataset == record.dataset && same_cell(rows[i].grid, record.grid)) return i;
  }
  rows.push_back(CostRow{record.method, record.dataset, record.grid});
  return rows.size() - 1;
}

struct Column {
  const char* csv;
  const char* title;
  std::string (*text)(const CostRow&);
};

const std::vector<Column>& columns() {
  static const std::vector<Column> table = {
      {"mflops", "MFLOPs", [](const CostRow& r) { return fmt::format("{:.1f}", r.mega_flops); }},
      {"params_m", "NP (M)", [](const CostRow& r) { return fmt::format("{:.3f}", r.parameters_millions); }},
      {"session_trainable_m", "trained in sessions (M)", [](const CostRow& r) { return fmt::format("{:.3f}", r.trainable_millions); }},
      {"it_ms", "IT (ms/sample)", [](const CostRow& r) { return fmt::format("{:.3f}", r.inference_ms_per_sample); }},
      {"base_train_s", "base training (s)", [](const CostRow& r) { return fmt::format("{:.1f}", r.base_train_seconds); }},
      {"update_s", "update per session (s)", [](const CostRow& r) { return fmt::format("{:.2f}", r.update_seconds); }},
      {"run_peak_mib", "memory of the run (MiB)", [](const CostRow& r) { return fmt::format("{:.0f}", r.run_peak_mib); }},
      {"replay_samples", "replay samples", [](const CostRow& r) { return fmt::format("{}", r.replay_samples); }},
      {"replay_mib", "replay memory (MiB)", [](const CostRow& r) { return fmt::format("{:.2f}", r.replay_mib); }},
  };
  return table;
}

bool any_cell(const std::vector<CostRow>& rows) {
  return std::any_of(rows.begin(), rows.end(), [](const CostRow& row) { return !row.grid.empty(); });
}

}  // namespace

std::string cost_row_label(const CostRow& row) {
  return label_with_cell(row.method, row.grid);
}

std::vector<CostRow> summarize_costs(const std::vector<RunRecord>& records) {
  std::vector<CostRow> rows;
  std::vector<std::size_t> update_counts;
  for (const auto& record : records) {
    const std::size_t index = row_index(rows, record);
    update_counts.resize(rows.size(), 0);
    CostRow& row = rows[index];
    ++row.runs;
    row.mega_flops = std::max(row.mega_flops, 2.0 * static_cast<double>(record.inference.macs) / 1e6);
    row.parameters_millions = std::max(row.parameters_millions, static_cast<double>(record.inference.parameters) / 1e6);
    row.trainable_millions =
        std::max(row.trainable_millions, static_cast<double>(record.inference.trainable_parameters) / 1e6);
    row.inference_ms_per_sample += 1e3 * record.inference.seconds_per_sample;
    for (std::size_t s = 0; s < record.sessions.size(); ++s) {
      const SessionOutcome& session = record.sessions[s];
      if (s == 0) {
        row.base_train_seconds += session.train_seconds;
      } else if (session.seen_classes >= record.sessions[s - 1].seen_classes) {  // a removing session trains nothing
        row.update_seconds += session.train_seconds;
        ++update_counts[index];
      }
    }
    row.run_peak_mib = std::max(row.run_peak_mib, static_cast<double>(run_peak_bytes(record)) / kMebibyte);
    row.replay_samples = std::max(row.replay_samples, record.replay_samples);
    row.replay_mib = std::max(row.replay_mib, static_cast<double>(record.replay_bytes) / kMebibyte);
  }
  for (std::size_t i = 0; i < rows.size(); ++i) {
    rows[i].base_train_seconds /= static_cast<double>(rows[i].runs);
    rows[i].inference_ms_per_sample /= static_cast<double>(rows[i].runs);
    if (update_counts[i] > 0) rows[i].update_seconds /= static_cast<double>(update_counts[i]);
  }
  return rows;
}

std::string render_cost_csv(const std::vector<CostRow>& rows) {
  const bool cells = any_cell(rows);
  std::string out = cells ? "method,dataset,cell,runs" : "method,dataset,runs";
  for (const auto& column : columns()) out += fmt::format(",{}", column.csv);
  out += "\n";
  for (const auto& row : rows) {
    out += cells ? fmt::format("{},{},{},{}", row.method, row.dataset, grid_cell_name(row.grid), row.runs)
                 : fmt::format("{},{},{}", row.method, row.dataset, row.runs);
    for (const auto& column : columns()) out += "," + column.text(row);
    out += "\n";
  }
  return out;
}

std::string render_cost_latex(const std::vector<CostRow>& rows) {
  // Eleven columns: the page's width (table*), scaled to it.
  std::string out = "% fscil-bench costs; requires \\usepackage{booktabs,graphicx}\n\\begin{table*}[!t]\n\\centering\n"
                    "\\caption{Cost of each method: FLOPs = 2 $\\times$ MACs per sample at inference, NP = parameters, IT = "
                    "inference time per sample (times: means over seeds; memory: largest).}\n";
  out += fmt::format("\\resizebox{{\\textwidth}}{{!}}{{\\begin{{tabular}}{{ll{}}}\n\\toprule\nMethod & Dataset",
                     std::string(columns().size(), 'r'));
  for (const auto& column : columns()) out += fmt::format(" & {}", column.title);
  out += " \\\\\n\\midrule\n";
  for (const auto& row : rows) {
    out += fmt::format("{} & {}", latex_text(cost_row_label(row)), latex_text(row.dataset));
    for (const auto& column : columns()) out += " & " + column.text(row);
    out += " \\\\\n";
  }
  return out + "\\bottomrule\n\\end{tabular}}\n\\end{table*}\n";
}

std::string render_cost_markdown(const std::vector<CostRow>& rows) {
  std::string out = "### costs (means over seeds; memory: largest)\n\n| method | dataset |";
  for (const auto& column : columns()) out += fmt::format(" {} |", column.title);
  out += "\n|---|---|";
  for (std::size_t c = 0; c < columns().size(); ++c) out += "---:|";
  out += "\n";
  for (const auto& row : rows) {
    out += fmt::format("| {} | {} |", cost_row_label(row), row.dataset);
    for (const auto& column : columns()) out += fmt::format(" {} |", column.text(row));
    out += "\n";
  }
  return out;
}

}  // namespace fscil
