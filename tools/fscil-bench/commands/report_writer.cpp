#include "tools/fscil-bench/commands/report_writer.h"

#include <fmt/format.h>

#include <algorithm>

#include "core/atomic_file.h"
#include "reports/cost_table.h"
#include "reports/figure_writer.h"
#include "reports/report_page.h"
#include "reports/run_figures.h"
#include "reports/paper_comparison.h"
#include "reports/summary_table.h"
#include "reports/tidy_sessions.h"
#include "reports/training_log.h"
#include "tools/fscil-bench/options/data_folder.h"

namespace fscil {

std::filesystem::path default_paper_tables() { return reference_file("paper_tables.csv"); }

std::string write_reports(const std::filesystem::path& out, const std::vector<RunRecord>& records,
                          const std::optional<std::filesystem::path>& paper_tables) {
  FileBatch files;
  const SummaryTable table = summarize_runs(records);
  files.add(out / "summary.csv", render_csv(table));
  files.add(out / "sessions.csv", render_tidy_sessions_csv(records));
  files.add(out / "results.tex", render_latex(table));
  const bool several_cells = std::any_of(records.begin(), records.end(),
                                        [&](const RunRecord& record) { return !same_cell(record.grid, records.front().grid); });
  for (const auto& record : records) {
    files.add(out / training_log_path(record, several_cells), render_training_log_csv(record));
  }
  const std::vector<CostRow> costs = summarize_costs(records);
  files.add(out / "costs.csv", render_cost_csv(costs));
  files.add(out / "costs.tex", render_cost_latex(costs));
  for (const auto& dataset : table.datasets()) {
    for (const SessionMetric metric : {SessionMetric::all, SessionMetric::base, SessionMetric::novel,
                                       SessionMetric::harmonic}) {
      add_figure(files, out, session_accuracy_figure(table, dataset, metric));
    }
    if (const Figure context = context_ratio_figure(records, dataset); !context.series.empty()) {
      add_figure(files, out, context);
    }
    for (const Figure& figure : efficiency_figures(costs, dataset)) add_figure(files, out, figure);
  }
  std::string markdown = render_markdown(table) + "\n" + render_cost_markdown(costs);
  if (paper_tables) {
    fmt::print(stderr, "{}", unfinished_warning(records));
    const auto rows = compare_with_paper(table, load_paper_tables(*paper_tables));
    files.add(out / "paper_comparison.csv", render_paper_comparison_csv(rows));
    markdown += "\n## Beside the paper\n\n" + render_paper_comparison_markdown(rows);
  }
  add_report_page(files, out);
  files.replace_all();
  return markdown;
}

}  // namespace fscil
