#include "tools/fscil-bench/command_line.h"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iostream>

#include "datasets/dataset_catalog.h"
#include "methods/method_registry.h"
#include "metrics/resource_usage.h"
#include "protocols/profiles.h"
#include "core/shown_text.h"
#include "core/stop_request.h"
#include "core/atomic_file.h"
#include "reports/context_analysis.h"
#include "reports/run_record.h"
#include "core/text_file.h"
#include "tools/fscil-bench/cells/bench_cells.h"
#include "tools/fscil-bench/cells/cell_runner.h"
#include "tools/fscil-bench/options/cli_error.h"
#include "tools/fscil-bench/options/cli_range.h"
#include "tools/fscil-bench/options/config_file.h"
#include "tools/fscil-bench/commands/logmel_command.h"
#include "tools/fscil-bench/options/machine_info.h"
#include "tools/fscil-bench/commands/reference_command.h"
#include "tools/fscil-bench/commands/report_writer.h"
#include "tools/fscil-bench/commands/reproduce_command.h"
#include "tools/fscil-bench/commands/rerun_command.h"
#include "tools/fscil-bench/commands/run_command.h"
#include "tools/fscil-bench/commands/slurm_command.h"
#include "tools/fscil-bench/commands/sweep_command.h"

namespace {

void print_catalogue() {
  fmt::print("methods:\n");
  for (const auto& entry : fscil::method_registry()) fmt::print("  {:<22} {}\n", entry.name, entry.summary);
  fmt::print("datasets:\n");
  for (const auto& entry : fscil::dataset_catalog()) fmt::print("  {:<22} {}\n", entry.name, entry.summary);
  fmt::print("profiles:\n");
  for (const auto& profile : fscil::profiles()) fmt::print("  {:<22} {}\n", profile.name, profile.summary);
}

void rebuild_reports(const std::string& results, const std::string& out, const std::string& methods,
                     const std::vector<std::string>& grid, bool paper, const std::string& paper_tables) {
  const auto records = fscil::load_command_records(results, methods, grid);
  const std::filesystem::path directory = out.empty() ? results : out;
  fmt::print("{}", fscil::write_reports(directory, records));
  if (paper) {
    fmt::print("\n## Beside the paper\n\n{}",
               fscil::write_paper_comparison(directory, records,
                                             paper_tables.empty() ? fscil::default_paper_tables() : std::filesystem::path(paper_tables)));
  }
}

// What cells and Slurm scripts run: this binary, by the path the kernel knows it by.
std::string this_executable() {
  std::error_code error;
  const auto path = std::filesystem::read_symlink("/proc/self/exe", error);
  if (error) throw std::runtime_error(fmt::format("/proc/self/exe: cannot read this program's path ({})", error.message()));
  return path.string();
}

void analyze_contexts(const std::string& results, const std::string& out) {
  const auto records = fscil::load_run_records(results);
  fscil::write_file_atomically(std::filesystem::path(out.empty() ? results : out) / "context_analysis.csv",
                               fscil::render_context_analysis_csv(records));
  fmt::print("{}", fscil::render_context_analysis_markdown(records));
}

}  // namespace

int fscil::run_command_line(int argc, char** argv) {
  fscil::close_method_registry();
  fscil::keep_freed_memory_for_reuse();
  CLI::App app{"fscil-bench: few-shot class-incremental learning benchmarks on tactile and audio signals"};
  app.set_help_all_flag("--help-all", "Help for every subcommand");
  app.set_version_flag("--version", fscil::version_text, "Release, commit and library versions, then exit");
  app.require_subcommand(0, 1);

  fscil::RunOptions run;
  app.add_option("--methods", run.methods,
                 "'all', 'ablation' (pits-sc and the four cop-fscil variants) or a comma-separated list of methods "
                 "(see: fscil-bench list)");
  app.add_option("--dataset", run.dataset, "dataset name (see: fscil-bench list)");
  app.add_option("--profile", run.profile, "smoke | fast | paper")->capture_default_str();
  app.add_option("--seeds", run.seeds, "seeds, e.g. 1,2,3 or 1-5")->capture_default_str();
  app.add_option("--threads", run.threads, "compute threads (0 = all cores)")
      ->check(fscil::within(fscil::ValidRange::at_least(0)))
      ->capture_default_str();
  app.add_option("--out", run.out, "output directory for result files and tables")->capture_default_str();
  std::string resume_dir;
  app.add_option("--resume", resume_dir,
                 "continue the interrupted command whose --out was DIR (give the same options): finished runs are "
                 "kept, a run stopped mid-way continues from its last session checkpoint");
  app.add_option("--data-root", run.data_root, "root folder of a real dataset download");
  app.add_option("--cache-dir", run.cache_dir, "cache folder: segments, and trained base sessions under stages/ (default: ~/.cache/fscil-bench)");
  app.add_flag("--no-cache", run.no_cache, "neither read nor write either cache");
  app.add_option("--max-memory", run.max_memory,
                 "SIZE (4G, 512M, bytes): a training pass that would take the run past it recomputes its ResNet "
                 "stem and stages in backward (as --set recompute=stages, the same numbers), and freed large "
                 "blocks go back to the kernel; an estimate, not a cap")
      ->check(CLI::Validator([](std::string& text) { return text.empty() ? std::string("expected a size such as 4G") : std::string(); },
                             "SIZE"));
  app.add_flag("--no-stage-cache", run.no_stage_cache, "train every base session, even one the cache holds for exactly these inputs");
  app.add_option("--features", run.features,
                 "auto | memory | on-demand: keep log-Mel features in memory, or compute each batch from the "
                 "signals (auto: in memory up to 1 GiB)")->capture_default_str();
  app.add_option("--split-mode", run.split_mode, "recording (grouped, default) | segment")->capture_default_str();
  app.add_option("--class-order", run.class_order, "natural | shuffled (from the seed)")->capture_default_str();
  app.add_option("--evaluate-on", run.evaluate_on,
                 "test | validation: score every session on the test split, or on the validation split of every "
                 "class (choose defaults there, never on test)")
      ->capture_default_str();
  app.add_option("--selection", run.selection,
                 "last | validation | test-oracle: which epoch a method keeps where the reference codes choose "
                 "one (last: the last epoch; validation: the best on base validation; test-oracle: the best on the "
                 "test split, as the reference codes do: inflated, labelled so in every table)")
      ->capture_default_str();
  app.add_option("--save-embeddings", run.save_embeddings,
                 "last | all | session numbers (0,9): keep the scored test embeddings of those sessions in "
                 "OUT/embeddings/RUN.h5 (for the embedding figure of fscil-bench reproduce embedding)");
  app.add_flag("--save-model", run.save_model,
               "keep each run's final method state in OUT/models/RUN.pt: a dict of named tensors that Python's "
               "torch.load reads");
  app.add_option("--set", run.assignments, "override a hyper-parameter or knob: key=value (repeatable)");
  app.add_flag("--quiet", run.quiet, "no progress on stderr");
  std::string config_file;
  app.add_option("--config", config_file,
                 "JSON file of run options: {\"methods\": \"all\", \"seeds\": \"1-5\", \"set\": {\"shot\": 5}, \"grid\": "
                 "{\"pspc_probes\": [5, 50]}}; options given on the command line override it");
  app.add_option("--cell", run.cell,
                 "run only cell K of this command (see: fscil-bench plan): its result files, no tables; continues "
                 "what --out holds of it")
      ->check(fscil::within(fscil::ValidRange::at_least(0)));

  auto* list = app.add_subcommand("list", "List methods, datasets and profiles, one line each");

  std::vector<std::string> grid;
  auto* sweep = app.add_subcommand(
      "sweep", "Run the command once per cell of the grid (every combination of the --grid values) into "
               "OUT/cells/, then tables over all cells with a column per key; takes every run option");
  sweep->add_option("--grid", grid,
                    "key=value1,value2,...: a --set key (or shot, way, selection) and its values (repeatable)")
      ->required();
  sweep->fallthrough();  // the run options (--methods, --dataset, --set, ...) belong to the main command

  // plan, slurm and run-cells take a run command's options, and --grid for a sweep's.
  std::vector<std::string> cells_grid;
  const auto add_grid = [&](CLI::App* command) {
    command->add_option("--grid", cells_grid, "key=value1,value2,...: the cells of a sweep (as for sweep; repeatable)");
    command->fallthrough();
  };
  auto* plan = app.add_subcommand(
      "plan", "List the cells of a run or sweep command, one line each (index, methods, dataset, grid cell, seed, "
              "cost class): the units --cell K, run-cells and slurm run; methods sharing a base session share a cell");
  add_grid(plan);
  bool plan_missing_only = false;
  plan->add_flag("--missing-only", plan_missing_only,
                 "only the cells without their result files; exit 1 when there are any (the Slurm merge job's check)");

  int jobs = 1;
  auto* run_cells_command = app.add_subcommand(
      "run-cells", "Run every cell of a run or sweep command as its own process, --jobs at a time with the threads "
                   "split between them (logs in OUT/cell-logs/), then the command's tables");
  add_grid(run_cells_command);
  run_cells_command->add_option("--jobs", jobs, "cells at a time")
      ->check(fscil::within(fscil::ValidRange::at_least(1)))
      ->capture_default_str();

  fscil::SlurmOptions slurm_options;
  auto* slurm = app.add_subcommand(
      "slurm", "Write OUT/slurm/array.sbatch (one Slurm array task per cell, SIGTERM-safe, requeued on preemption) and "
               "OUT/slurm/merge.sbatch (the tables, after the array); --submit submits both");
  add_grid(slurm);
  slurm->add_option("--partition", slurm_options.partition, "Slurm partition");
  slurm->add_option("--time", slurm_options.time, "time limit per task (e.g. 4:00:00)");
  slurm->add_option("--cpus-per-task", slurm_options.cpus_per_task, "CPUs per task, its --threads (default: --threads, or 1)")
      ->check(fscil::within(fscil::ValidRange::at_least(1)));
  slurm->add_option("--mem", slurm_options.mem, "memory per task (e.g. 8G)");
  slurm->add_option("--max-parallel", slurm_options.max_parallel, "at most K tasks at once (--array=...%K)")
      ->check(fscil::within(fscil::ValidRange::at_least(1)));
  slurm->add_option("--sbatch-arg", slurm_options.sbatch_arguments, "another #SBATCH line, e.g. --account=abc (repeatable)");
  slurm->add_flag("--submit", slurm_options.submit, "submit both scripts through sbatch and print the job ids");
  slurm->add_flag("--missing-only", slurm_options.missing_only,
                  "only the cells without their result files (after a failure, a preemption or a time limit)");

  std::string rerun_file;
  auto* rerun = app.add_subcommand(
      "rerun", "Run again exactly the run a result file records (method, dataset, profile, seed, threads, split, "
               "selection, grid cell and every parameter), into --out (default: rerun)");
  rerun->add_option("result", rerun_file, "a result file (OUT/results/RUN.json)")->required();
  rerun->fallthrough();

  std::string reproduction;
  bool list_reproductions = false;
  auto* reproduce = app.add_subcommand(
      "reproduce", "Run one of the paper's tables or figures and write it in the paper's layout (NAME.tex, .md, "
                   ".csv, figures/, index.html), our numbers beside the paper's; takes the run options but --methods "
                   "(default --out: reproductions/NAME/DATASET)");
  reproduce->add_option("name", reproduction, "which one (see: fscil-bench reproduce --list)");
  reproduce->add_flag("--list", list_reproductions, "name every reproduction, its caption and what it runs");
  reproduce->fallthrough();

  fscil::LogMelOptions logmel;
  auto* logmel_command = app.add_subcommand("logmel", "Compute log-Mel spectrograms of an HDF5 signal");
  logmel_command->add_option("--input", logmel.input, "HDF5 file with dataset /signal (float32, C x L)")->required();
  logmel_command->add_option("--output", logmel.output, "HDF5 file to write /logmel (float32, C x M x T)")->required();
  logmel_command->add_option("--sample-rate", logmel.settings.sample_rate, "sample rate in Hz")
      ->check(fscil::within(fscil::ValidRange::above(0)))
      ->required();
  logmel_command->add_option("--n-fft", logmel.settings.n_fft, "FFT size")
      ->check(fscil::within(fscil::ValidRange::at_least(2)))
      ->required();
  logmel_command->add_option("--hop", logmel.settings.hop, "hop in samples")
      ->check(fscil::within(fscil::ValidRange::at_least(1)))
      ->required();
  logmel_command->add_option("--n-mels", logmel.settings.n_mels, "Mel bins")
      ->check(fscil::within(fscil::ValidRange::at_least(1)))
      ->required();
  logmel.settings.center = false;
  logmel_command->add_flag("--center", logmel.settings.center, "reflect-pad n_fft/2 on both sides");
  logmel_command->add_option("--mel-scale", logmel.mel_scale, "htk | slaney")->capture_default_str();
  logmel_command->add_option("--mel-norm", logmel.mel_norm, "none | slaney")->capture_default_str();
  logmel_command->add_option("--threads", logmel.threads, "threads (0 = all cores)")
      ->check(fscil::within(fscil::ValidRange::at_least(0)));

  std::string results_dir, report_out;
  auto* report = app.add_subcommand(
      "report", "Rebuild summary.csv, results.tex, costs.csv, costs.tex and the Markdown tables from result files");
  report->add_option("--results", results_dir, "directory holding result JSON files")->required();
  report->add_option("--out", report_out, "where to write the tables (default: the results directory)");
  std::string report_methods;
  std::vector<std::string> report_grid;
  report->add_option("--methods", report_methods, "the --methods of the command the results are of: rows in that order");
  report->add_option("--grid", report_grid, "the --grid of the sweep the results are of: its cells in that order");
  bool report_paper = false;
  std::string paper_tables;
  report->add_flag("--paper", report_paper,
                   "also write paper_comparison.csv: our numbers beside the paper's, with the difference");
  report->add_option("--paper-tables", paper_tables, "the paper's tables (default: reports/reference/paper_tables.csv)");

  std::string analyze_results, analyze_out;
  auto* analyze = app.add_subcommand("analyze", "Context-to-class dispersion R per session from result files");
  analyze->add_option("--results", analyze_results, "directory holding result JSON files")->required();
  analyze->add_option("--out", analyze_out, "where to write context_analysis.csv (default: the results directory)");

  std::string check_results, check_reference_file;
  auto* check = app.add_subcommand("check", "Compare result files with stored reference numbers (exit 1 on any drift)");
  check->add_option("--results", check_results, "directory holding result JSON files")->required();
  check->add_option("--reference", check_reference_file, "reference CSV (e.g. reports/reference/simtex-mini-smoke.csv)")
      ->required();

  std::string reference_results, reference_out;
  double reference_tolerance = 2.0;
  auto* reference = app.add_subcommand("reference", "Write reference numbers from result files (for check)");
  reference->add_option("--results", reference_results, "directory holding result JSON files")->required();
  reference->add_option("--out", reference_out, "reference CSV to write")->required();
  reference->add_option("--tolerance", reference_tolerance, "two-sided tolerance of every value, percentage points")
      ->check(fscil::within(fscil::ValidRange::at_least(0)))
      ->capture_default_str();

  try {
    std::vector<std::string> arguments(argv, argv + argc);
    if (const std::string config = fscil::config_file_of(arguments); !config.empty()) {
      arguments = fscil::with_config_file(arguments, config, [&](const std::string& name) {
        return app.get_option_no_throw(name) != nullptr;
      });
    }
    std::vector<char*> words;
    for (auto& argument : arguments) words.push_back(argument.data());
    app.parse(static_cast<int>(words.size()), words.data());
  } catch (const fscil::CliError& error) {
    fmt::print(stderr, "fscil-bench: error: {}\n", fscil::shown_text(error.what(), 2000));
    return 2;
  } catch (const CLI::ParseError& error) {
    if (error.get_exit_code() == 0) return app.exit(error);  // --help, --help-all
    fmt::print(stderr, "fscil-bench: error: {} (try: fscil-bench --help)\n", fscil::shown_text(error.what(), 2000));
    return 2;
  }
  if (!resume_dir.empty()) {
    if (app.count("--out") > 0 && run.out != resume_dir) {
      fmt::print(stderr, "fscil-bench: error: --resume {} and --out {}: a resumed run writes where it started\n",
                 resume_dir, run.out);
      return 2;
    }
    run.out = resume_dir;
    run.resume = true;
  }
  const bool runs_one_command = app.get_subcommands().empty() || sweep->parsed();
  if (run.cell >= 0 && !runs_one_command) {
    fmt::print(stderr, "fscil-bench: error: --cell: expected a run or sweep command (see: fscil-bench plan)\n");
    return 2;
  }
  int status = 0;
  try {
    if (list->parsed()) {
      print_catalogue();
    } else if (reproduce->parsed() && (list_reproductions || reproduction.empty())) {
      if (!list_reproductions) {
        fmt::print(stderr, "fscil-bench: error: reproduce: expected a NAME or --list\n");
        return 2;
      }
      fmt::print("{}", fscil::list_reproductions());
    } else if (logmel_command->parsed()) {
      fscil::run_logmel(logmel);
    } else if (report->parsed()) {
      rebuild_reports(results_dir, report_out, report_methods, report_grid, report_paper, paper_tables);
    } else if (analyze->parsed()) {
      analyze_contexts(analyze_results, analyze_out);
    } else if (check->parsed()) {
      status = fscil::check_reference(check_results, check_reference_file);
    } else if (reference->parsed()) {
      fscil::write_reference(reference_results, reference_out, reference_tolerance);
    } else if (plan->parsed()) {
      auto cells = fscil::plan_cells(run, cells_grid);
      if (plan_missing_only) {
        cells.erase(std::remove_if(cells.begin(), cells.end(),
                                   [&](const fscil::BenchCell& cell) { return fscil::cell_has_results(run, cell); }),
                    cells.end());
        status = cells.empty() ? 0 : 1;
      }
      fmt::print("{}", fscil::render_plan(cells));
    } else if (slurm->parsed()) {
      fmt::print("{}", fscil::run_slurm(run, cells_grid, slurm_options, this_executable()));
    } else {
      // The main job, a sweep of it, a reproduction, one cell of them, or every cell.
      fscil::install_stop_handlers();
      if (reproduce->parsed()) {
        if (app.count("--out") == 0 && resume_dir.empty()) run.out = "reproductions/" + reproduction + "/" + run.dataset;
      } else if (rerun->parsed()) {
        for (const char* shaping : {"--methods", "--dataset", "--profile", "--seeds", "--threads", "--split-mode",
                                    "--class-order", "--evaluate-on", "--selection", "--max-memory", "--set", "--cell"}) {
          if (app.count(shaping) > 0) {
            fmt::print(stderr, "fscil-bench: error: rerun {}: {} comes from the result file; use a run command to "
                               "change it\n", rerun_file, shaping);
            return 2;
          }
        }
        if (app.count("--out") == 0 && resume_dir.empty()) run.out = "rerun";
        run = fscil::rerun_options(
            fscil::run_record_from_json_text(fscil::read_text_file(rerun_file), rerun_file), run);
      } else if (run.methods.empty() || run.dataset.empty()) {
        fmt::print(stderr, "fscil-bench: error: --methods and --dataset are required (try: fscil-bench list, --help)\n");
        return 2;
      }
      fmt::print("{}", reproduce->parsed()           ? fscil::run_reproduction(reproduction, run)
                       : run_cells_command->parsed() ? fscil::run_cells(run, cells_grid, jobs, this_executable())
                       : run.cell >= 0               ? fscil::run_cell(run, sweep->parsed() ? grid : std::vector<std::string>{}, run.cell)
                       : sweep->parsed()             ? fscil::run_sweep(run, grid)
                                                     : fscil::run_benchmark(run));
    }
    // Tables printed to a full disk or a closed pipe are a failure, not a success.
    errno = 0;
    if (std::fflush(stdout) != 0 || std::ferror(stdout)) {
      throw std::runtime_error(
          fmt::format("standard output: cannot write ({})", errno != 0 ? std::strerror(errno) : "write error"));
    }
  } catch (const fscil::StopRequested& stop) {
    // Finished runs keep their result files, the run in progress its last session's checkpoint.
    fmt::print(stderr, "fscil-bench: {}: finished sessions are kept; continue with the same command and --resume "
                       "(a --cell continues by itself)\n", stop.what());
    return 128 + stop.signal();
  } catch (const std::exception& error) {
    // One line naming what was wrong; earlier result files stay as they were written.
    std::string message = error.what();
    if (const auto newline = message.find('\n'); newline != std::string::npos) message.resize(newline);
    // Whatever a library put in its message, no raw byte reaches the terminal.
    fmt::print(stderr, "fscil-bench: error: {}\n", fscil::shown_text(message, 2000));
    return 1;
  }
  return status;
}
