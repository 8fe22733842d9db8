#include "reports/context_analysis.h"

#include <fmt/format.h>

#include <cmath>

#include "metrics/statistics.h"
#include "core/error.h"
#include "reports/summary_table.h"

namespace fscil {

namespace {

struct ContextRow {
  const SummaryRow* summary;
  std::vector<double> ratio_mean, ratio_max;  // per session, mean over seeds
};

std::vector<ContextRow> context_rows(const SummaryTable& table, const std::vector<RunRecord>& records) {
  std::vector<ContextRow> rows;
  for (const auto& summary : table.rows) {
    ContextRow row{&summary, {}, {}};
    std::vector<std::vector<double>> means, maxima;
    for (const auto& record : records) {
      if (record.method != summary.method || record.dataset != summary.dataset) continue;
      means.resize(record.sessions.size());
      maxima.resize(record.sessions.size());
      for (std::size_t s = 0; s < record.sessions.size(); ++s) {
        if (std::isnan(record.sessions[s].context_ratio_mean)) continue;
        means[s].push_back(record.sessions[s].context_ratio_mean);
        maxima[s].push_back(record.sessions[s].context_ratio_max);
      }
    }
    if (means.empty() || means.front().empty()) continue;
    for (std::size_t s = 0; s < means.size(); ++s) {
      row.ratio_mean.push_back(mean_of(means[s]));
      row.ratio_max.push_back(mean_of(maxima[s]));
    }
    rows.push_back(row);
  }
  if (rows.empty()) throw ReportError("no result file records the context ratio R (the dataset has no known contexts)");
  return rows;
}

}  // namespace

std::string render_context_analysis_csv(const std::vector<RunRecord>& records) {
  const SummaryTable table = summarize_runs(records);
  std::string out = "method,dataset,seeds,AA,session,R_mean,R_max\n";
  for (const auto& row : context_rows(table, records)) {
    for (std::size_t s = 0; s < row.ratio_mean.size(); ++s) {
      out += fmt::format("{},{},{},{:.4f},{},{:.4f},{:.4f}\n", row.summary->method, row.summary->dataset,
                         fmt::join(row.summary->seeds, " "), row.summary->average_accuracy.mean, s, row.ratio_mean[s],
                         row.ratio_max[s]);
    }
  }
  return out;
}

std::string render_context_analysis_markdown(const std::vector<RunRecord>& records) {
  const SummaryTable table = summarize_runs(records);
  const auto rows = context_rows(table, records);
  std::size_t sessions = 0;
  for (const auto& row : rows) sessions = std::max(sessions, row.ratio_mean.size());
  std::string out = "### context-to-class dispersion R of the test embeddings (mean over seeds)\n\n| method | dataset | AA | R |";
  for (std::size_t s = 0; s < sessions; ++s) out += fmt::format(" {} |", s);
  out += "\n|---|---|---:|---|";
  for (std::size_t s = 0; s < sessions; ++s) out += "---:|";
  out += "\n";
  for (const auto& row : rows) {
    for (const auto& [label, values] : {std::make_pair("mean", &row.ratio_mean), std::make_pair("max", &row.ratio_max)}) {
      out += fmt::format("| {} | {} | {:.2f} | {} |", row.summary->method, row.summary->dataset,
                         row.summary->average_accuracy.mean, label);
      for (double value : *values) out += fmt::format(" {:.3f} |", value);
      out += "\n";
    }
  }
  return out + "\n";
}

}  // namespace fscil
