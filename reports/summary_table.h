#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "metrics/convergence.h"
#include "reports/run_record.h"

namespace fscil {

// A mean over seeds with its sample standard deviation and the half-width of its 95% confidence
// interval (Student t with seeds - 1 degrees of freedom): the mean is in [mean - ci95, mean + ci95].
struct SeedStatistic {
  double mean = 0;
  double std = 0;
  double ci95 = 0;
  std::vector<double> values;  // per seed, in the order of the row's seeds: what paired tests compare
};

// One (method, dataset) row: per-session accuracy and AA/PD/ADR over its seeds. AA/PD/ADR are
// computed per seed, then averaged.
struct SummaryRow {
  std::string method;
  std::string dataset;
  GridCell grid;                    // the sweep cell (RunRecord::grid)
  std::string selection = "last";  // RunRecord::selection
  std::vector<std::uint64_t> seeds;
  std::vector<SeedStatistic> session_accuracy;
  // Per session, on the base classes' samples, on the novel classes' samples and their harmonic
  // mean (the novel ones and the harmonic mean are 0 in the base session).
  std::vector<SeedStatistic> session_base_accuracy, session_novel_accuracy, session_harmonic_mean;
  SeedStatistic average_accuracy, performance_drop, average_drop_rate;
  // Whether its base training had finished (metrics/convergence.h) over its seeds: still rising
  // if any seed's is, and per such seed and stage what was still rising ("seed 2, pretrain: ...").
  TrainingVerdict training = TrainingVerdict::not_recorded;
  std::vector<std::string> unfinished;
  // RunRecord::method_note of its runs (distinct wordings joined by "; "): its rows' footnote.
  std::string method_note;
};

struct SummaryTable {
  std::vector<SummaryRow> rows;  // in order of first appearance
  std::string evaluated_on = "test";  // the split every run was scored on (RunRecord::evaluated_on)
  std::string precision = "fp32";     // what every run's encoder computed in (precision_of)
  std::string removal = "none";       // protocol_parameters' removal: "fciac" for class-variable sessions
  // What a title or caption adds for runs unlike the usual ones: ", encoder in bf16", ",
  // class-variable sessions (removal=fciac)"; "" for fp32 add-only runs, named as they always were.
  std::string title_note() const;
  bool several_seeds() const;
  std::vector<std::string> datasets() const;
  // The sweep keys of any row but selection (a column of its own), in order of first appearance:
  // columns of every rendering.
  std::vector<std::string> grid_keys() const;
};

// What a row is called in a table: the method, and for a selection other than the last epoch how
// its epochs were chosen ("selected on test (inflated)": never to be read as an honest result).
std::string row_label(const SummaryRow& row);

// The base training's verdict over seeds: still rising if any seed's is; converged if every
// seed's is; otherwise unjudged, or not recorded where no seed's log scored base validation.
TrainingVerdict seeds_verdict(const std::vector<TrainingVerdict>& verdicts);
// The rows of `rows` whose base training was still rising, each note as "method [cell], seed N,
// stage: ..." for a table's footnote; empty when every row finished.
std::vector<std::string> unfinished_notes(const std::vector<const SummaryRow*>& rows);
// A table's footnotes of the methods' notes: one per distinct note, "method [cell], ...: note".
std::vector<std::string> method_notes(const std::vector<const SummaryRow*>& rows);
// "warning: ..." lines naming every run of `records` with a base stage that ended still rising
// (check and report --paper print them: such a number was not measured at its plateau); empty
// when none. Judged run by run, so it never refuses what summarize_runs would.
std::string unfinished_warning(const std::vector<RunRecord>& records);

// Groups records by (method, dataset, sweep cell, selection). Throws ReportError when runs of one group disagree on
// the number of sessions or repeat a seed, and when some runs were scored on the test split and
// others on the validation split, or made in other precisions: one table never mixes them.
SummaryTable summarize_runs(const std::vector<RunRecord>& records);

// Renderers of the same table: CSV for scripts, LaTeX in the paper's layout (best in bold),
// Markdown for the terminal.
std::string render_csv(const SummaryTable& table);
// One table per dataset, its caption led by `what` ("Comparison on simtex, test split ...").
std::string render_latex(const SummaryTable& table, const std::string& what = "Comparison");
std::string render_markdown(const SummaryTable& table);

}  // namespace fscil
