#include "reports/summary_table.h"

#include <fmt/format.h>

#include <algorithm>
#include <set>
#include <tuple>

#include "metrics/fscil_metrics.h"
#include "metrics/statistics.h"
#include "core/error.h"

namespace fscil {

namespace {
SeedStatistic statistic_of(const std::vector<double>& values) {
  return {mean_of(values), standard_deviation_of(values), confidence_half_width_95(values), values};
}

// The base session's stages as the run logged them; none for a run without sessions.
std::vector<StageConvergence> base_stages(const RunRecord& record) {
  return record.sessions.empty() ? std::vector<StageConvergence>{} : judge_stages(record.sessions.front().training_log);
}

}  // namespace

std::string SummaryTable::title_note() const {
  std::string note = precision == "fp32" ? std::string() : ", encoder in " + precision;
  if (removal != "none") note += ", class-variable sessions (removal=" + removal + ")";
  return note;
}

bool SummaryTable::several_seeds() const {
  return std::any_of(rows.begin(), rows.end(), [](const SummaryRow& row) { return row.seeds.size() > 1; });
}

std::vector<std::string> SummaryTable::datasets() const {
  std::vector<std::string> names;
  for (const auto& row : rows) {
    if (std::find(names.begin(), names.end(), row.dataset) == names.end()) names.push_back(row.dataset);
  }
  return names;
}

std::vector<std::string> SummaryTable::grid_keys() const {
  std::vector<std::string> keys;
  for (const auto& row : rows) add_new_keys(without_key(row.grid, "selection"), keys);  // selection has its own column
  return keys;
}

std::string row_label(const SummaryRow& row) {
  if (row.selection == "test-oracle") return row.method + " (selected on test (inflated))";
  if (row.selection == "validation") return row.method + " (selected on validation)";
  return row.method;
}

TrainingVerdict seeds_verdict(const std::vector<TrainingVerdict>& verdicts) {
  const auto any = [&](TrainingVerdict verdict) {
    return std::find(verdicts.begin(), verdicts.end(), verdict) != verdicts.end();
  };
  if (verdicts.empty() || std::all_of(verdicts.begin(), verdicts.end(),
                                      [](TrainingVerdict v) { return v == TrainingVerdict::not_recorded; })) {
    return TrainingVerdict::not_recorded;
  }
  if (any(TrainingVerdict::not_learning)) return TrainingVerdict::not_learning;
  if (any(TrainingVerdict::still_rising)) return TrainingVerdict::still_rising;
  if (any(TrainingVerdict::unjudged) || any(TrainingVerdict::not_recorded)) return TrainingVerdict::unjudged;
  return TrainingVerdict::converged;
}

std::vector<std::string> unfinished_notes(const std::vector<const SummaryRow*>& rows) {
  std::vector<std::string> notes;
  for (const auto* row : rows) {
    const std::string label = label_with_cell(row_label(*row), row->grid);
    for (const auto& note : row->unfinished) notes.push_back(label + ", " + note);
  }
  return notes;
}

std::vector<std::string> method_notes(const std::vector<const SummaryRow*>& rows) {
  std::vector<std::pair<std::string, std::vector<std::string>>> labels_of_note;  // in order of first appearance
  for (const auto* row : rows) {
    if (row->method_note.empty()) continue;
    auto same = std::find_if(labels_of_note.begin(), labels_of_note.end(),
                             [&](const auto& entry) { return entry.first == row->method_note; });
    if (same == labels_of_note.end()) {
      labels_of_note.emplace_back(row->method_note, std::vector<std::string>{});
      same = labels_of_note.end() - 1;
    }
    same->second.push_back(label_with_cell(row_label(*row), row->grid));
  }
  std::vector<std::string> notes;
  for (const auto& [note, labels] : labels_of_note) notes.push_back(fmt::format("{}: {}", fmt::join(labels, ", "), note));
  return notes;
}

std::string unfinished_warning(const std::vector<RunRecord>& records) {
  std::string out;
  for (const RunRecord& record : records) {
    const std::string label = label_with_cell(record.method, record.grid);
    for (const StageConvergence& stage : base_stages(record)) {
      if (!ended_unfinished(stage.verdict)) continue;
      out += fmt::format("warning: {}, seed {}: a base stage ended {}: {}\n", label, record.seed,
                         stage.verdict == TrainingVerdict::not_learning
                             ? "without learning"
                             : "still rising on base validation, not at its plateau",
                         describe_stage(stage));
    }
  }
  return out;
}

SummaryTable summarize_runs(const std::vector<RunRecord>& records) {
  using Key = std::tuple<std::string, std::string, GridCell, std::string>;
  const auto key_of = [](const RunRecord& record) {
    return Key(record.method, record.dataset, record.grid, record.selection);
  };
  std::vector<Key> keys;
  for (const auto& record : records) {
    if (std::find(keys.begin(), keys.end(), key_of(record)) == keys.end()) keys.push_back(key_of(record));
  }
  SummaryTable table;
  if (!records.empty()) {
    table.evaluated_on = records.front().evaluated_on;
    table.precision = precision_of(records.front());
    table.removal = removal_of(records.front());
  }
  for (const auto& record : records) {
    if (record.evaluated_on != table.evaluated_on) {
      throw ReportError(fmt::format("{} on {} seed {} was scored on the {} split, {} on {} seed {} on the {} split: "
                                    "report them from separate directories", records.front().method,
                                    records.front().dataset, records.front().seed, table.evaluated_on, record.method,
                                    record.dataset, record.seed, record.evaluated_on));
    }
    if (removal_of(record) != table.removal) {
      throw ReportError(fmt::format("{} on {} seed {} ran with removal={}, {} on {} seed {} with removal={}: report "
                                    "them from separate directories", records.front().method, records.front().dataset,
                                    records.front().seed, table.removal, record.method, record.dataset, record.seed,
                                    removal_of(record)));
    }
    if (precision_of(record) != table.precision) {
      throw ReportError(fmt::format("{} on {} seed {} was made in {}, {} on {} seed {} in {}: report them from "
                                    "separate directories", records.front().method, records.front().dataset,
                                    records.front().seed, table.precision, record.method, record.dataset, record.seed,
                                    precision_of(record)));
    }
  }
  for (const auto& key : keys) {
    const auto& [method, dataset, grid, selection] = key;
    SummaryRow row;
    row.method = method;
    row.dataset = dataset;
    row.grid = grid;
    row.selection = selection;
    std::vector<std::vector<double>> per_session, base_per_session, novel_per_session, harmonic_per_session;
    std::vector<double> aa, pd, adr;
    std::vector<TrainingVerdict> verdicts;
    for (const auto& record : records) {
      if (key_of(record) != key) continue;
      if (std::find(row.seeds.begin(), row.seeds.end(), record.seed) != row.seeds.end()) {
        throw ReportError(fmt::format("{} on {}: seed {} appears in two result files", method, dataset, record.seed));
      }
      const auto accuracies = record.session_accuracies();
      if (!per_session.empty() && per_session.size() != accuracies.size()) {
        throw ReportError(fmt::format("{} on {}: runs with {} and {} sessions cannot be averaged", method, dataset,
                                      per_session.size(), accuracies.size()));
      }
      per_session.resize(accuracies.size());
      base_per_session.resize(accuracies.size());
      novel_per_session.resize(accuracies.size());
      harmonic_per_session.resize(accuracies.size());
      for (std::size_t s = 0; s < accuracies.size(); ++s) {
        per_session[s].push_back(accuracies[s]);
        base_per_session[s].push_back(record.sessions[s].accuracy.base);
        novel_per_session[s].push_back(record.sessions[s].accuracy.novel);
        harmonic_per_session[s].push_back(record.sessions[s].accuracy.harmonic);
      }
      const FscilSummary summary = summarize_sessions(accuracies);
      aa.push_back(summary.average_accuracy);
      pd.push_back(summary.performance_drop);
      adr.push_back(summary.average_drop_rate);
      row.seeds.push_back(record.seed);
      // Seeds from different builds may word the note differently: every distinct wording is kept.
      if (!record.method_note.empty() && row.method_note.find(record.method_note) == std::string::npos) {
        row.method_note += (row.method_note.empty() ? "" : "; ") + record.method_note;
      }
      const std::vector<StageConvergence> stages = base_stages(record);
      verdicts.push_back(run_verdict(stages));
      for (const auto& stage : stages) {
        if (!ended_unfinished(stage.verdict)) continue;
        row.unfinished.push_back(fmt::format("seed {}, {}", record.seed, describe_stage(stage)));
      }
    }
    row.training = seeds_verdict(verdicts);
    for (std::size_t s = 0; s < per_session.size(); ++s) {
      row.session_accuracy.push_back(statistic_of(per_session[s]));
      row.session_base_accuracy.push_back(statistic_of(base_per_session[s]));
      row.session_novel_accuracy.push_back(statistic_of(novel_per_session[s]));
      row.session_harmonic_mean.push_back(statistic_of(harmonic_per_session[s]));
    }
    row.average_accuracy = statistic_of(aa);
    row.performance_drop = statistic_of(pd);
    row.average_drop_rate = statistic_of(adr);
    table.rows.push_back(std::move(row));
  }
  return table;
}

}  // namespace fscil
