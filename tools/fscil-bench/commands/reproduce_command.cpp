#include "tools/fscil-bench/commands/reproduce_command.h"

#include <fmt/format.h>

#include <filesystem>
#include <functional>

#include "core/atomic_file.h"
#include "reports/cost_table.h"
#include "reports/figure_writer.h"
#include "reports/paper_comparison.h"
#include "reports/paper_tables.h"
#include "reports/report_page.h"
#include "reports/run_figures.h"
#include "reports/selection_bias.h"
#include "reports/setting_table.h"
#include "reports/summary_table.h"
#include "core/error.h"
#include "tools/fscil-bench/cells/bench_cells.h"
#include "tools/fscil-bench/options/data_folder.h"
#include "tools/fscil-bench/options/help_text.h"
#include "reports/embedding_figure.h"
#include "tools/fscil-bench/commands/report_writer.h"
#include "tools/fscil-bench/commands/sweep_command.h"
#include "tools/fscil-bench/options/sweep_grid.h"

namespace fscil {

namespace fs = std::filesystem;

namespace {

// What a reproduction's writer gets: the results folder, its runs, the dataset and the grid it swept.
struct Results {
  fs::path out;
  std::string dataset;
  std::vector<GridAxis> axes;
  std::vector<RunRecord> records;
  SummaryTable table;
  std::vector<CostRow> costs;
  // The reproduction's figures and tables, written with its page at the end, together.
  FileBatch files;
};

// The three renderings of a reproduction's table, written as OUT/NAME.{md,csv,tex}.
struct Rendered {
  std::string markdown, csv, latex;
};

struct Reproduction {
  const char* name;
  const char* caption;  // the paper's
  const char* runs;     // what is run, in words
  const char* methods;
  std::vector<std::string> grid;     // empty: one run command, no sweep
  const char* save_embeddings;       // --save-embeddings of its runs ("" for none)
  std::function<Rendered(Results&)> write;
};

fs::path paper_file(const char* name) { return reference_file(name); }

// Our rows beside the paper's results or ablation table (test-split runs of a dataset it reports);
// our table alone, saying why, where there is nothing to set beside it. `what` leads the caption.
Rendered beside_paper(const Results& results, const std::string& what) {
  std::string why_alone;
  if (results.table.evaluated_on != "test") {
    why_alone = "Scored on validation: no comparison with the paper's test-split numbers.\n";
  } else if (results.table.precision != "fp32") {
    why_alone = fmt::format("The encoder computed in {}: no comparison with the paper's fp32 numbers.\n",
                            results.table.precision);
  } else if (results.table.removal != "none") {
    why_alone = "Sessions also removed classes: no comparison with the paper's add-only sessions.\n";
  } else if (paper_dataset_of(results.dataset).empty()) {
    why_alone = fmt::format("{} is not a dataset of the paper nor a simulation of one: nothing to set beside its "
                            "rows.\n", results.dataset);
  }
  if (!why_alone.empty()) {
    return {render_markdown(results.table) + "\n" + why_alone, render_csv(results.table),
            render_latex(results.table, what)};
  }
  const auto rows = compare_with_paper(results.table, load_paper_tables(paper_file("paper_tables.csv")));
  return {render_markdown(results.table) + "\n" + render_paper_comparison_markdown(rows),
          render_paper_comparison_csv(rows), render_latex(results.table, what)};
}

// The swept keys as the paper's analysis tables name them, for their LaTeX rows.
const std::vector<std::pair<std::string, std::string>>& paper_key_names() {
  static const std::vector<std::pair<std::string, std::string>> names = {
      {"pic_weight", "$\\lambda$"},
      {"cpi_reference", "Reference statistics"},
      {"cpi_support_coverage", "Support coverage"},
      {"cpi_query_coverage", "Query coverage"},
      {"shot", "Shots"},
      {"pspc_probes", "$N_{\\mathrm{ps}}$"}};
  return names;
}

Rendered setting_table(const Results& results, const char* name, const char* caption, const char* method,
                       bool update_time = false) {
  const SettingTable table = make_setting_table(name, caption, method, results.dataset, results.table, results.costs,
                                                load_paper_analyses(paper_file("paper_analyses.csv")), update_time,
                                                paper_key_names());
  return {render_setting_markdown(table), render_setting_csv(table), render_setting_latex(table)};
}

// Figures of a metric against the reproduction's (first) sweep key, one per metric.
void add_grid_figures(Results& results, const std::vector<std::string>& metrics, const std::string& what) {
  const GridAxis& axis = results.axes.front();
  const std::string& key = axis.key;
  for (const auto& metric : metrics) {
    add_figure(results.files, results.out, grid_metric_figure(results.table, results.dataset, key, axis.values, metric,
                                                 fmt::format("{}_{}_{}", what, results.dataset, metric),
                                                 fmt::format("{} against {} on {}", metric, key, results.dataset)));
  }
}

const std::vector<Reproduction>& reproductions() {
  static const std::vector<Reproduction> catalogue = {
      {"results", "Comparison on HapTex, LMT108, LS-100 and NS-100 (Tables II-V); accuracy per session (Fig. 5)",
       "every method, one run per seed", "all", {}, "",
       [](Results& results) { return beside_paper(results, "Comparison"); }},
      {"ablation", "Progressive ablation on HapTex and LMT108 (Tables VI-VII) and its figure",
       "pits-sc and the four cop-fscil variants", "ablation", {}, "",
       [](Results& results) {
         add_figure(results.files, results.out, ablation_figure(results.table, results.dataset, "ablation_" + results.dataset));
         return beside_paper(results, "Progressive ablation");
       }},
      {"efficiency", "Computational efficiency: FLOPs, parameters (NP) and inference time (IT) of each method",
       "every method, one run per seed; the cost table", "all", {}, "",
       [](Results& results) {
         // efficiency_DATASET_{flops,params,it} are among the figures every report writes.
         return Rendered{render_cost_markdown(results.costs), render_cost_csv(results.costs),
                         render_cost_latex(results.costs)};
       }},
      {"lambda", "Sensitivity analysis of the loss weight lambda for L_PIC on HapTex",
       "cop-fscil over pic_weight = 0, 1, 0.1, 0.01, 0.001, 0.0001", "cop-fscil",
       {"pic_weight=0,1,0.1,0.01,0.001,0.0001"}, "",
       [](Results& results) {
         add_grid_figures(results, {"AA", "PD"}, "lambda");
         return setting_table(results, "lambda", "Sensitivity analysis of the loss weight lambda for L_PIC",
                              "cop-fscil");
       }},
      {"reference-selection", "Effect of pseudo-context statistic transfer strategies in CPI",
       "cop-fscil with random and with farthest reference statistics", "cop-fscil", {"cpi_reference=random,farthest"},
       "",
       [](Results& results) {
         return setting_table(results, "reference-selection",
                              "Effect of pseudo-context statistic transfer strategies in CPI", "cop-fscil");
       }},
      {"cpi-coverage", "Effect of different CPI coverage settings on support and query samples",
       "cop-fscil over CPI coverage of support and query samples, 100% and 60% each", "cop-fscil",
       {"cpi_support_coverage=1,0.6", "cpi_query_coverage=1,0.6"}, "",
       [](Results& results) {
         return setting_table(results, "cpi-coverage",
                              "Effect of different CPI coverage settings on support and query samples", "cop-fscil");
       }},
      {"fewer-shot", "Average Accuracy and Performance Drop with different numbers of shots during incremental sessions",
       "pits-sc and cop-fscil with 1 to 5 shots per novel class", "pits-sc,cop-fscil", {"shot=1,2,3,4,5"}, "",
       [](Results& results) {
         add_grid_figures(results, {"AA", "PD"}, "fewer_shot");
         Rendered both;
         for (const char* method : {"pits-sc", "cop-fscil"}) {
           const Rendered one = setting_table(results, "fewer-shot", "AA and PD with fewer shots", method);
           both.markdown += one.markdown;
           both.csv += both.csv.empty() ? one.csv : one.csv.substr(one.csv.find('\n') + 1);
           both.latex += one.latex;
         }
         return both;
       }},
      {"nps", "Incremental update time under different values of N_ps, and PSPC's sensitivity to N_ps",
       "cop-fscil over N_ps = 5, 10, 50, 100, 500, 1000 (the base is trained once: N_ps acts in sessions only)",
       "cop-fscil", {"pspc_probes=5,10,50,100,500,1000"}, "",
       [](Results& results) {
         add_grid_figures(results, {"AA"}, "nps");
         const GridAxis& probes = results.axes.front();
         add_figure(results.files, results.out, grid_update_time_figure(results.costs, results.dataset, probes.key,
                                                           probes.values, "nps_update_time_" + results.dataset,
                                                           "Incremental update time against N_ps on " + results.dataset));
         return setting_table(results, "nps", "Incremental update time under different values of N_ps", "cop-fscil",
                              true);
       }},
      {"context", "Context-to-class dispersion R per session (context analysis)",
       "pits-sc and cop-fscil, one run per seed; R of the test embeddings after every session", "pits-sc,cop-fscil",
       {}, "",
       [](Results& results) {
         // context_ratio_DATASET is among the figures every report writes.
         const Figure figure = context_ratio_figure(results.records, results.dataset);
         std::string csv = "method,session,R\n", markdown = "### R per session (mean over seeds)\n\n";
         for (const auto& series : figure.series) {
           for (std::size_t s = 0; s < series.x.size(); ++s) {
             csv += fmt::format("{},{},{:.4f}\n", series.label, series.x[s], series.y[s]);
           }
           markdown += fmt::format("- {}: {:.3f}\n", series.label, fmt::join(series.y, ", "));
         }
         if (figure.series.empty()) markdown += "This dataset carries no acquisition contexts: R is not measured.\n";
         return Rendered{markdown, csv, render_latex(results.table)};
       }},
      {"embedding", "Embedding-space visualisation of PITS-SC and CoP-FSCIL (5 base + 5 novel classes, PCA, unit circle)",
       "pits-sc and cop-fscil with --save-embeddings last", "pits-sc,cop-fscil", {}, "last",
       [](Results& results) {
         std::string markdown = "### Embedding figures\n\n";
         for (const auto& record : results.records) {
           const fs::path file = results.out / "embeddings" /
                                 fs::path(run_record_file_name(record)).replace_extension(".h5");
           const std::string name = fmt::format("embedding_{}_seed{}", record.method, record.seed);
           add_figure(results.files, results.out, embedding_figure(file, name, fmt::format("{} on {}, last session, seed {}",
                                                                              record.method, record.dataset, record.seed)));
           markdown += fmt::format("- figures/{}.svg\n", name);
         }
         return Rendered{markdown, "", ""};
       }},
      {"selection-bias", "Selection bias: what choosing epochs on the test set adds to AA",
       "pits-sc and orco with the last epoch, the best on validation and the best on test (the reference codes' "
       "habit)", "pits-sc,orco", {"selection=last,validation,test-oracle"}, "",
       [](Results& results) {
         const auto rows = measure_selection_bias(results.table);
         return Rendered{render_selection_bias_markdown(rows), render_selection_bias_csv(rows),
                         render_selection_bias_latex(rows)};
       }},
  };
  return catalogue;
}

}  // namespace

std::string list_reproductions() {
  std::string out;
  for (const auto& reproduction : reproductions()) {
    const std::string runs = fmt::format("runs: {}{}", reproduction.runs, reproduction.grid.empty() ? "" :
                                         fmt::format(" (--grid {})", fmt::join(reproduction.grid, " --grid ")));
    out += labelled_lines(reproduction.name, reproduction.caption, 21) + '\n' + labelled_lines("", runs, 21) + '\n';
  }
  return out;
}

std::vector<std::pair<std::string, std::string>> reproduction_captions() {
  std::vector<std::pair<std::string, std::string>> captions;
  for (const auto& reproduction : reproductions()) captions.emplace_back(reproduction.name, reproduction.caption);
  return captions;
}

std::string run_reproduction(const std::string& name, RunOptions options) {
  const auto& catalogue = reproductions();
  const auto found = std::find_if(catalogue.begin(), catalogue.end(),
                                  [&](const Reproduction& reproduction) { return name == reproduction.name; });
  if (found == catalogue.end()) {
    throw CliError(fmt::format("reproduce {}: no such reproduction (see: fscil-bench reproduce --list)", name));
  }
  if (!options.methods.empty()) throw CliError(fmt::format("reproduce {}: runs its own methods; leave out --methods", name));
  if (options.dataset.empty()) throw CliError(fmt::format("reproduce {}: --dataset is required", name));
  options.methods = found->methods;
  options.save_embeddings = found->save_embeddings;
  if (found->grid.empty()) {
    run_benchmark(options);
  } else {
    run_sweep(options, found->grid);
  }
  Results results{options.out, options.dataset, found->grid.empty() ? std::vector<GridAxis>() : parse_grid(found->grid),
                  load_command_records(options.out, found->methods, found->grid), {},
                  {}, {}};
  results.table = summarize_runs(results.records);
  results.costs = summarize_costs(results.records);
  const Rendered rendered = found->write(results);
  const fs::path stem = fs::path(options.out) / name;
  FileBatch& files = results.files;
  files.add(fs::path(stem).replace_extension(".md"), rendered.markdown);
  if (!rendered.csv.empty()) files.add(fs::path(stem).replace_extension(".csv"), rendered.csv);
  if (!rendered.latex.empty()) files.add(fs::path(stem).replace_extension(".tex"), rendered.latex);
  add_report_page(files, options.out);
  files.replace_all();
  return rendered.markdown + fmt::format("Reproduction {0}: {1}/{0}.md, .csv, .tex; figures in {1}/figures/; open "
                                         "{1}/index.html\n", name, options.out);
}

}  // namespace fscil
