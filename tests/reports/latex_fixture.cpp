// Writes every kind of .tex the program writes (the results table, of three seeds and as the
// ablation, the cost table, a reproduction's setting table, the selection-bias table, line and bar
// figures with seeds' whiskers, one on a logarithmic axis; the embedding figure's scatter comes from the same pgfplots writer) from made-up runs
// with names LaTeX must escape, for the LaTeX test
// (tests/reports/latex_compile_test.sh): fscil_latex_fixture DIR.
#include <cstdio>
#include <exception>
#include <filesystem>

#include "core/atomic_file.h"
#include "reports/cost_table.h"
#include "reports/figure_writer.h"
#include "reports/run_figures.h"
#include "reports/selection_bias.h"
#include "reports/setting_table.h"
#include "reports/summary_table.h"
#include "tests/reports/session_runs.h"

int main(int argc, char** argv) {
  using namespace fscil;
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s DIR\n", argv[0]);
    return 2;
  }
  try {
    const std::filesystem::path folder = argv[1];
    std::vector<RunRecord> runs;
    for (std::uint64_t seed = 1; seed <= 3; ++seed) {
      const double shift = static_cast<double>(seed);
      runs.push_back(run_with_accuracies("prototype", "simtex", seed, {90 + shift, 80, 71 - shift}));
      runs.push_back(run_with_accuracies("cop-fscil/cpi+pspc", "simtex", seed, {92, 83 + shift, 75}));
      runs.push_back(run_with_accuracies("cop-fscil/cpi+pspc", "lab_2024&co", seed, {60 + shift, 50, 40}));
      // A method's note is free text from a result file: every LaTeX special, as text.
      runs.back().method_note = "our reading: \\input{x} ~ ^ {braces} & 100% #1 $5 a_b";
    }
    const SummaryTable three_seeds = summarize_runs(runs);
    write_file_atomically(folder / "results.tex", render_latex(three_seeds));
    write_file_atomically(folder / "ablation.tex", render_latex(summarize_runs({runs[0], runs[1]}), "Progressive ablation"));
    const std::vector<CostRow> costs = summarize_costs(runs);
    write_file_atomically(folder / "costs.tex", render_cost_latex(costs));

    std::vector<RunRecord> swept;
    for (const char* probes : {"5", "50", "1000"}) {
      for (std::uint64_t seed = 1; seed <= 2; ++seed) {  // two seeds: the figures draw whiskers
        const double shift = static_cast<double>(seed);
        swept.push_back(in_cell(run_with_accuracies("cop-fscil", "simtex", seed, {90, 80 + shift, 70}),
                                {{"pspc_probes", probes}}));
      }
    }
    const SummaryTable sweep = summarize_runs(swept);
    write_file_atomically(folder / "nps.tex",
                          render_setting_latex(make_setting_table("nps", "Accuracy against N_ps", "cop-fscil", "simtex",
                                                                  sweep, summarize_costs(swept), {}, true,
                                                                  {{"pspc_probes", "$N_{\\mathrm{ps}}$"}})));
    std::vector<RunRecord> selections;
    for (const char* selection : {"last", "test-oracle"}) {
      RunRecord run = run_with_accuracies("orco", "simtex", 1, {90, 70});
      run.selection = selection;
      selections.push_back(in_cell(run, {{"selection", selection}}, selection));
    }
    write_file_atomically(folder / "selection-bias.tex",
                          render_selection_bias_latex(measure_selection_bias(summarize_runs(selections))));

    write_figure(folder, session_accuracy_figure(three_seeds, "simtex", SessionMetric::all));
    for (const Figure& figure : efficiency_figures(costs, "simtex")) write_figure(folder, figure);
    write_figure(folder, ablation_figure(three_seeds, "simtex", "ablation_simtex"));
    write_figure(folder, grid_metric_figure(sweep, "simtex", "pspc_probes", {"5", "50", "1000"}, "AA", "nps_simtex_AA",
                                            "AA against N_ps"));
  } catch (const std::exception& error) {
    std::fprintf(stderr, "%s\n", error.what());
    return 1;
  }
  return 0;
}
