#include "reports/paper_comparison.h"

#include <fmt/format.h>

#include <algorithm>

#include "core/csv_text.h"
#include "core/error.h"

namespace fscil {

namespace {

struct DatasetMatch {
  const char* ours;
  const char* paper;
  const char* table_suffix;
  bool simulated;
};

const DatasetMatch kDatasets[] = {
    {"haptex", "HapTex", "haptex", false}, {"lmt108", "LMT108", "lmt108", false},
    {"ls100", "LS-100", "ls100", false},   {"ns100", "NS-100", "ns100", false},
    {"simtex", "HapTex", "haptex", true},  {"simtex-lmt", "LMT108", "lmt108", true},
};

// Our method name -> the table and row name the paper prints it under.
std::pair<std::string, std::string> paper_row_of(const std::string& method, const std::string& suffix) {
  if (method == "cop-fscil") return {"results_" + suffix, "CoP-FSCIL"};
  if (method == "pits-sc") return {"results_" + suffix, "PITS-SC"};
  if (method == "orco") return {"results_" + suffix, "OrCo"};
  if (method == "adbs") return {"results_" + suffix, "ADBS"};
  if (method == "pan") return {"results_" + suffix, "PAN"};
  if (method == "pa-pct") return {"results_" + suffix, "PA-PCT"};
  if (method == "dsn") return {"results_" + suffix, "DSN"};
  if (method == "comp-fscil") return {"results_" + suffix, "Comp-FSCIL"};
  if (method == "arp") return {"results_" + suffix, "ARP"};
  if (method == "amfo") return {"results_" + suffix, "AMFO"};
  if (method == "ldc") return {"results_" + suffix, "LDC"};
  if (method.rfind("cop-fscil/", 0) == 0) return {"ablation_" + suffix, method};
  return {};
}

std::vector<double> values_of(const std::vector<double>& sessions, std::size_t count, double pd, double aa,
                              double adr) {
  std::vector<double> values(sessions.begin(), sessions.begin() + static_cast<std::ptrdiff_t>(count));
  values.insert(values.end(), {pd, aa, adr});
  return values;
}

std::string column_names(std::size_t sessions) {
  std::string names;
  for (std::size_t s = 0; s < sessions; ++s) names += fmt::format("acc_{},", s);
  return names + "PD,AA,ADR";
}

std::string label_of(const PaperComparisonRow& row) {
  return row.simulated ? fmt::format("{} (simulated {})", row.dataset, row.paper_dataset) : row.dataset;
}

}  // namespace

std::string paper_dataset_of(const std::string& dataset, bool* simulated) {
  for (const auto& match : kDatasets) {
    if (dataset != match.ours) continue;
    if (simulated != nullptr) *simulated = match.simulated;
    return match.paper;
  }
  return "";
}

std::vector<PaperComparisonRow> compare_with_paper(const SummaryTable& ours, const std::vector<PaperRow>& paper) {
  if (ours.evaluated_on != "test") {
    throw ReportError(fmt::format("these runs were scored on the {} split; the paper's numbers are test-split numbers",
                                  ours.evaluated_on));
  }
  if (ours.precision != "fp32") {
    throw ReportError(fmt::format("these runs' encoder computed in {}; the paper's numbers are fp32 numbers",
                                  ours.precision));
  }
  if (ours.removal != "none") {
    throw ReportError(fmt::format("these runs' sessions also removed classes (removal={}); the paper's sessions only "
                                  "add them", ours.removal));
  }
  std::vector<PaperComparisonRow> rows;
  for (const auto& row : ours.rows) {
    const auto dataset = std::find_if(std::begin(kDatasets), std::end(kDatasets),
                                      [&](const DatasetMatch& match) { return row.dataset == match.ours; });
    if (dataset == std::end(kDatasets)) continue;
    const auto [table, name] = paper_row_of(row.method, dataset->table_suffix);
    const auto published = std::find_if(paper.begin(), paper.end(), [&, &table = table, &name = name](const PaperRow& p) {
      return p.table == table && p.method == name;
    });
    if (published == paper.end()) continue;
    PaperComparisonRow compared{row.dataset, row.method, dataset->paper, table, name, dataset->simulated, {}, {}, 0,
                                row.method_note};
    compared.sessions = std::min(row.session_accuracy.size(), published->session_accuracy.size());
    std::vector<double> means;
    for (const auto& statistic : row.session_accuracy) means.push_back(statistic.mean);
    compared.ours = values_of(means, compared.sessions, row.performance_drop.mean, row.average_accuracy.mean,
                              row.average_drop_rate.mean);
    compared.paper = values_of(published->session_accuracy, compared.sessions, published->performance_drop,
                               published->average_accuracy, published->average_drop_rate);
    rows.push_back(std::move(compared));
  }
  return rows;
}

std::string render_paper_comparison_csv(const std::vector<PaperComparisonRow>& rows) {
  std::size_t sessions = 0;
  for (const auto& row : rows) sessions = std::max(sessions, row.sessions);
  std::string out =
      fmt::format("dataset,method,source,simulated,paper_dataset,paper_table,paper_method,{},method_note\n",
                  column_names(sessions));
  for (const auto& row : rows) {
    const auto line = [&](const char* source, const std::vector<double>& values) {
      // The paper's own numbers are of the real data, whatever ours are of.
      const bool simulated = row.simulated && std::string(source) != "paper";
      out += fmt::format("{},{},{},{},{},{},{}", row.dataset, row.method, source, simulated ? "yes" : "no",
                         row.paper_dataset, row.paper_table, row.paper_method);
      for (std::size_t s = 0; s < sessions; ++s) out += s < row.sessions ? fmt::format(",{:.2f}", values[s]) : ",";
      for (std::size_t k = row.sessions; k < values.size(); ++k) out += fmt::format(",{:.2f}", values[k]);
      // The note is about our numbers: on our line only.
      out += fmt::format(",{}\n", std::string(source) == "ours" ? csv_field(row.method_note) : "");
    };
    std::vector<double> difference(row.ours.size());
    for (std::size_t k = 0; k < difference.size(); ++k) difference[k] = row.ours[k] - row.paper[k];
    line("ours", row.ours);
    line("paper", row.paper);
    line("ours-paper", difference);
  }
  return out;
}

std::string render_paper_comparison_markdown(const std::vector<PaperComparisonRow>& rows) {
  if (rows.empty()) return "No run matches a dataset and method the paper reports.\n";
  std::string out;
  for (const auto& row : rows) {
    out += fmt::format("### {} on {} beside the paper ({} on {}, table {}){}\n\n", row.method, label_of(row),
                       row.paper_method, row.paper_dataset, row.paper_table,
                       row.simulated ? ": our data are simulated, the paper's real" : "");
    if (!row.method_note.empty()) out += fmt::format("‡ ours: {}.\n\n", row.method_note);
    out += "| | ";
    for (std::size_t s = 0; s < row.sessions; ++s) out += fmt::format("{} | ", s);
    out += "PD | AA | ADR |\n|---|";
    for (std::size_t k = 0; k < row.ours.size(); ++k) out += "---:|";
    out += "\n";
    const auto line = [&](const std::string& label, const std::vector<double>& values, const char* format) {
      out += fmt::format("| {} |", label);
      for (double value : values) out += fmt::format(fmt::runtime(format), value);
      out += "\n";
    };
    std::vector<double> difference(row.ours.size());
    for (std::size_t k = 0; k < difference.size(); ++k) difference[k] = row.ours[k] - row.paper[k];
    line("ours", row.ours, " {:.2f} |");
    line("paper", row.paper, " {:.2f} |");
    line("ours - paper", difference, " {:+.2f} |");
    out += "\n";
  }
  return out;
}

}  // namespace fscil
