#include "tools/report_writer.h"

#include "reports/atomic_file.h"
#include "reports/summary_table.h"

namespace fscil {

std::string write_reports(const std::filesystem::path& out, const std::vector<RunRecord>& records) {
  const SummaryTable table = summarize_runs(records);
  write_file_atomically(out / "summary.csv", render_csv(table));
  write_file_atomically(out / "results.tex", render_latex(table));
  return render_markdown(table);
}

}  // namespace fscil
