#include "tools/fscil-bench/commands/command_table.h"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <optional>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/parallel_for.h"
#include "core/text_file.h"
#include "datasets/dataset_catalog.h"
#include "methods/method_registry.h"
#include "protocols/profiles.h"
#include "reports/context_analysis.h"
#include "reports/paper_tables.h"
#include "reports/reference_numbers.h"
#include "reports/run_record.h"
#include "tools/fscil-bench/cells/bench_cells.h"
#include "tools/fscil-bench/cells/cell_runner.h"
#include "tools/fscil-bench/cells/out_folder_lock.h"
#include "tools/fscil-bench/cells/time_estimate.h"
#include "tools/fscil-bench/commands/logmel_command.h"
#include "tools/fscil-bench/commands/reference_command.h"
#include "tools/fscil-bench/commands/report_writer.h"
#include "tools/fscil-bench/commands/reproduce_command.h"
#include "tools/fscil-bench/commands/rerun_command.h"
#include "tools/fscil-bench/commands/slurm_command.h"
#include "tools/fscil-bench/commands/sweep_command.h"
#include "tools/fscil-bench/options/cli_range.h"
#include "tools/fscil-bench/options/help_text.h"
#include "tools/fscil-bench/options/run_option_table.h"

namespace fscil {

bool Invocation::given(const char* option) const { return app.count(option) > 0; }

std::string Invocation::executable() const {
  std::error_code error;
  const auto path = std::filesystem::read_symlink("/proc/self/exe", error);
  if (error) throw Error(fmt::format("/proc/self/exe: cannot read this program's path ({})", error.message()));
  return path.string();
}

void Invocation::require_methods_and_dataset() const {
  if (run.methods.empty() || run.dataset.empty()) {
    throw CliError("--methods and --dataset are required (try: fscil-bench list, --help)");
  }
}

namespace {

// --results of every command that reads an --out folder, and --out of those that write their
// tables into it by default.
const CLI::Validator kAFolder = refusing_empty("expected the --out folder of a run");
const CLI::Validator kTablesFolder = refusing_empty("expected a folder; leave the option out for the results folder");

// The lock on --out of a command that writes tables from `results`: another folder than the
// results' is claimed as a run's --out is, since its files may be the user's.
std::optional<OutFolderLock> claim_tables_folder(const std::string& out, const std::string& results) {
  if (!out.empty()) refuse_output_among_run_files("--out", out, results);
  if (out.empty() || std::filesystem::weakly_canonical(out) == std::filesystem::weakly_canonical(results)) return {};
  return std::optional<OutFolderLock>(std::in_place, out);
}

// `--grid key=value1,...` (repeatable): the cells of a sweep.
void add_grid_option(CLI::App& command, std::vector<std::string>& grid, const char* help) {
  command.add_option("--grid", grid, help);
}

class ListCommand : public Subcommand {
 public:
  void declare(CLI::App&) override {}
  int run(Invocation&) override {
    const auto line = [](const std::string& name, const std::string& summary) {
      fmt::print("{}\n", labelled_lines("  " + name, summary, 25));
    };
    fmt::print("methods:\n");
    for (const auto& entry : method_registry()) line(entry.name, entry.summary);
    fmt::print("datasets:\n");
    for (const auto& entry : dataset_catalog()) line(entry.name, entry.summary);
    fmt::print("profiles:\n");
    for (const auto& profile : profiles()) line(profile.name, profile.summary);
    fmt::print("reproductions (fscil-bench reproduce NAME --dataset D):\n");
    for (const auto& [name, caption] : reproduction_captions()) line(name, caption);
    return exit_status::success;
  }
};

class SweepCommand : public Subcommand {
 public:
  void declare(CLI::App& command) override {
    add_grid_option(command, grid_, "key=value1,value2,...: a --set key (or shot, way, selection) and its values (repeatable)");
    command.get_option("--grid")->required();
    command.fallthrough();  // the run options (--methods, --dataset, --set, ...) belong to the main command
  }
  int run(Invocation& invocation) override {
    invocation.require_methods_and_dataset();
    const RunOptions& run = invocation.run;
    fmt::print("{}", run.cell >= 0 ? run_cell(run, grid_, run.cell) : run_sweep(run, grid_));
    return exit_status::success;
  }
  bool trains() const override { return true; }
  bool takes_cell() const override { return true; }

 private:
  std::vector<std::string> grid_;
};

// plan, run-cells and slurm take a run command's options, and --grid for a sweep's.
class CellsCommand : public Subcommand {
 public:
  void declare(CLI::App& command) override {
    add_grid_option(command, grid_, "key=value1,value2,...: the cells of a sweep (as for sweep; repeatable)");
    command.fallthrough();
    declare_own(command);
  }

 protected:
  virtual void declare_own(CLI::App& command) = 0;
  std::vector<std::string> grid_;
};

class PlanCommand : public CellsCommand {
  void declare_own(CLI::App& command) override {
    command.add_flag("--missing-only", missing_only_,
                     "only the cells without their result files; exit 1 when there are any (the Slurm merge job's check)");
    command.add_flag("--no-estimate", no_estimate_,
                     "list the cells without estimating their time (which, once per machine and input shape, times "
                     "the training step); every cell is still checked, which prepares the dataset");
  }
  int run(Invocation& invocation) override {
    auto cells = plan_cells(invocation.run, grid_);
    std::vector<std::string> notes;  // what the estimate rests on, and whether bf16 pays here
    // A listing of cells that cannot run is no plan: each is checked (the estimate checks as it sizes).
    if (missing_only_ || no_estimate_) {
      check_every_cell(invocation.run, grid_);
    } else {
      try {
        const std::vector<Calibration> calibrations = estimate_cells(invocation.run, grid_, cells);
        bool idle = true;
        for (const Calibration& calibration : calibrations) {
          notes.push_back("estimate's basis: " + calibration.basis);
          idle = idle && calibration.idle;
        }
        // Two loaded calibrations make no ratio, and without the cache each plan would time bf16 anew.
        notes.push_back(idle && !invocation.run.no_cache && !calibrations.empty()
                            ? bf16_note(calibrations.front())
                            : "--precision bf16: not timed by this plan (machine loaded, or --no-cache)");
      } catch (const DataNotHere& error) {  // a real dataset on a machine without its data: the cells still list
        for (BenchCell& cell : cells) cell.estimated_seconds = -1;
        fmt::print(stderr, "fscil-bench plan: no time estimate: {}\n", error.what());
      }
    }
    if (!missing_only_) add_measured_seconds(invocation.run, cells);  // those cells are not listed then
    int status = exit_status::success;
    if (missing_only_) {
      cells.erase(std::remove_if(cells.begin(), cells.end(),
                                 [&](const BenchCell& cell) { return cell_has_results(invocation.run, cell); }),
                  cells.end());
      status = cells.empty() ? exit_status::success : exit_status::bad_input;
    }
    fmt::print("{}", render_plan(cells));
    if (const std::string removal = removal_of_command(invocation.run, grid_); !removal.empty()) {
      fmt::print("{}\n", removal);
    }
    for (const std::string& note : notes) fmt::print("{}\n", note);
    return status;
  }
  bool missing_only_ = false;
  bool no_estimate_ = false;
};

class RunCellsCommand : public CellsCommand {
  void declare_own(CLI::App& command) override {
    command.add_option("--jobs", jobs_, "cells at a time")
        ->check(within(ValidRange::between(1, kMaxThreads)))
        ->capture_default_str();
  }
  int run(Invocation& invocation) override {
    invocation.require_methods_and_dataset();
    fmt::print("{}", run_cells(invocation.run, grid_, jobs_, invocation.executable()));
    return exit_status::success;
  }
  bool trains() const override { return true; }
  int jobs_ = 1;
};

class SlurmCommand : public CellsCommand {
  void declare_own(CLI::App& command) override {
    command.add_option("--partition", slurm_.partition, "Slurm partition");
    command.add_option("--time", slurm_.time, "time limit per task (e.g. 4:00:00)");
    command.add_option("--cpus-per-task", slurm_.cpus_per_task, "CPUs per task, its --threads (default: --threads, or 1)")
        ->check(within(ValidRange::between(1, kMaxThreads)));
    command.add_option("--mem", slurm_.mem, "memory per task (e.g. 8G)");
    command.add_option("--max-parallel", slurm_.max_parallel, "at most K tasks at once (--array=...%K)")
        ->check(within(ValidRange::at_least(1)));
    command.add_option("--sbatch-arg", slurm_.sbatch_arguments, "another #SBATCH line, e.g. --account=abc (repeatable)");
    command.add_flag("--submit", slurm_.submit, "submit both scripts through sbatch and print the job ids");
    command.add_flag("--missing-only", slurm_.missing_only,
                     "only the cells without their result files (after a failure, a preemption or a time limit)");
  }
  int run(Invocation& invocation) override {
    fmt::print("{}", run_slurm(invocation.run, grid_, slurm_, invocation.executable()));
    return exit_status::success;
  }
  SlurmOptions slurm_;
};

class RerunCommand : public Subcommand {
 public:
  void declare(CLI::App& command) override {
    command.add_option("result", file_, "a result file (OUT/results/RUN.json)")->required();
    command.fallthrough();
  }
  int run(Invocation& invocation) override {
    for (const auto& option : run_option_table()) {
      if (option.from_result_file && invocation.given(option.name)) {
        throw CliError(fmt::format("rerun {}: {} comes from the result file; use a run command to change it", file_,
                                   option.name));
      }
    }
    RunOptions& run = invocation.run;
    if (!invocation.given("--out") && invocation.resume_dir.empty()) run.out = "rerun";
    never_replace(file_);
    const RunRecord record = read_run_record(file_);
    require_profile(record.profile, file_);
    // A result file may hold more threads than --threads takes (--threads 0 on a larger node), but
    // not more than this machine has or --threads takes, whichever is more: 100000 written in a
    // file would start 100000 threads.
    if (const int most = std::max(kMaxThreads, thread_count(0)); record.threads > most) {
      throw ReportError(fmt::format("rerun {}: threads {}, expected at most {} (--threads' {} or this machine's "
                                    "hardware threads, whichever is more)", file_, record.threads, most, kMaxThreads));
    }
    run = rerun_options(record, file_, run);
    std::error_code error;
    const auto replaced = std::filesystem::path(run.out) / "results" / std::filesystem::path(file_).filename();
    if (std::filesystem::equivalent(replaced, file_, error)) {
      throw CliError(fmt::format("rerun {}: --out {} holds this result file, which the rerun would replace (and its "
                                 "times with it); give another --out", file_, run.out));
    }
    fmt::print("{}", run_benchmark(run));
    return exit_status::success;
  }
  bool trains() const override { return true; }

 private:
  std::string file_;
};

class ReproduceCommand : public Subcommand {
 public:
  void declare(CLI::App& command) override {
    command.add_option("name", name_, "which one (see: fscil-bench reproduce --list)");
    command.add_flag("--list", list_, "name every reproduction, its caption and what it runs");
    command.fallthrough();
  }
  int run(Invocation& invocation) override {
    if (list_ || name_.empty()) {
      if (!list_) throw CliError("reproduce: expected a NAME or --list");
      if (!name_.empty()) throw CliError(fmt::format("reproduce {} --list: give a NAME or --list, not both", name_));
      for (const RunOption& option : run_option_table()) {  // a listing runs nothing: they would go unread
        if (invocation.given(option.name)) {
          throw CliError(fmt::format("reproduce --list: {} is read only when a reproduction runs", option.name));
        }
      }
      fmt::print("{}", list_reproductions());
      return exit_status::success;
    }
    RunOptions& run = invocation.run;
    if (!invocation.given("--out") && invocation.resume_dir.empty()) run.out = "reproductions/" + name_ + "/" + run.dataset;
    fmt::print("{}", run_reproduction(name_, run));
    return exit_status::success;
  }
  bool trains() const override { return true; }

 private:
  std::string name_;
  bool list_ = false;
};

class LogMelCommand : public Subcommand {
 public:
  void declare(CLI::App& command) override {
    command.add_option("--input", options_.input, "HDF5 file with dataset /signal (float32, C x L)")->required();
    command.add_option("--output", options_.output, "HDF5 file to write /logmel (float32, C x M x T)")->required();
    command.add_option("--sample-rate", options_.settings.sample_rate, "sample rate in Hz")
        ->check(within(ValidRange::above_up_to(0, LogMelSettings::kMaxSampleRate)))
        ->required();
    command.add_option("--n-fft", options_.settings.n_fft, "FFT size")->check(within(ValidRange::at_least(2)))->required();
    command.add_option("--hop", options_.settings.hop, "hop in samples")->check(within(ValidRange::at_least(1)))->required();
    command.add_option("--n-mels", options_.settings.n_mels, "Mel bins")->check(within(ValidRange::at_least(1)))->required();
    options_.settings.center = false;
    command.add_flag("--center", options_.settings.center, "reflect-pad n_fft/2 on both sides");
    command.add_option("--mel-scale", options_.mel_scale, "htk | slaney")->capture_default_str();
    command.add_option("--mel-norm", options_.mel_norm, "none | slaney")->capture_default_str();
    command.add_option("--threads", options_.threads, "threads (0 = all cores)")
        ->check(within(ValidRange::between(0, kMaxThreads)));
  }
  int run(Invocation&) override {
    run_logmel(options_);
    return exit_status::success;
  }

 private:
  LogMelOptions options_;
};

class ReportCommand : public Subcommand {
 public:
  void declare(CLI::App& command) override {
    command.add_option("--results", results_, "directory holding result JSON files")->required()->check(kAFolder);
    command.add_option("--out", out_, "where to write the tables (default: the results directory)")
        ->check(kTablesFolder);
    command.add_option("--methods", methods_, "the --methods of the command the results are of: rows in that order");
    command.add_option("--grid", grid_, "the --grid of the sweep the results are of: its cells in that order");
    command.add_flag("--paper", paper_, "also write paper_comparison.csv: our numbers beside the paper's, with the difference");
    command.add_option("--paper-tables", paper_tables_, "the paper's tables (default: reports/reference/paper_tables.csv)");
  }
  int run(Invocation&) override {
    if (!paper_ && !paper_tables_.empty()) {
      throw CliError("--paper-tables: read only with --paper (the comparison it feeds); add --paper or drop it");
    }
    refuse_folder_being_written(results_);
    const auto records = load_command_records(results_, methods_, grid_);
    require_results_of_the_command(records, results_, methods_, grid_);
    const std::filesystem::path tables = paper_tables_.empty() ? default_paper_tables() : std::filesystem::path(paper_tables_);
    if (paper_) load_paper_tables(tables);  // a bad file is refused before any table is written
    const std::filesystem::path directory = out_.empty() ? results_ : out_;
    const std::optional<OutFolderLock> claimed = claim_tables_folder(out_, results_);
    fmt::print("{}", write_reports(directory, records, paper_ ? std::optional(tables) : std::nullopt));
    return exit_status::success;
  }

 private:
  std::string results_, out_, methods_, paper_tables_;
  std::vector<std::string> grid_;
  bool paper_ = false;
};

class AnalyzeCommand : public Subcommand {
 public:
  void declare(CLI::App& command) override {
    command.add_option("--results", results_, "directory holding result JSON files")->required()->check(kAFolder);
    command.add_option("--out", out_, "where to write context_analysis.csv (default: the results directory)")
        ->check(kTablesFolder);
  }
  int run(Invocation&) override {
    refuse_folder_being_written(results_);
    const auto records = load_command_records(results_, "", {});
    const std::optional<OutFolderLock> claimed = claim_tables_folder(out_, results_);
    write_file_atomically(std::filesystem::path(out_.empty() ? results_ : out_) / "context_analysis.csv",
                          render_context_analysis_csv(records));
    fmt::print("{}", render_context_analysis_markdown(records));
    return exit_status::success;
  }

 private:
  std::string results_, out_;
};

class CheckCommand : public Subcommand {
 public:
  void declare(CLI::App& command) override {
    command.add_option("--results", results_, "directory holding result JSON files")->required()->check(kAFolder);
    command.add_option("--reference", reference_, "reference CSV (e.g. reports/reference/simtex-mini-smoke.csv)")
        ->required()
        ->check(refusing_empty("expected a reference CSV"));
  }
  int run(Invocation&) override {
    refuse_folder_being_written(results_);
    return check_reference(results_, reference_);
  }

 private:
  std::string results_, reference_;
};

class ReferenceCommand : public Subcommand {
 public:
  void declare(CLI::App& command) override {
    command.add_option("--results", results_, "directory holding result JSON files")->required()->check(kAFolder);
    command.add_option("--out", out_, "reference CSV to write")->required()->check(refusing_empty("expected a file"));
    command.add_option("--tolerance", tolerance_, "two-sided tolerance of every value, percentage points")
        ->check(within(reference_tolerance_range()))
        ->capture_default_str();
  }
  int run(Invocation&) override {
    refuse_folder_being_written(results_);
    refuse_output_among_run_files("--out", out_, results_);
    write_reference(results_, out_, tolerance_);
    return exit_status::success;
  }

 private:
  std::string results_, out_;
  double tolerance_ = 2.0;
};

template <typename T>
std::unique_ptr<Subcommand> make() {
  return std::make_unique<T>();
}

}  // namespace

const std::vector<SubcommandEntry>& subcommand_table() {
  static const std::vector<SubcommandEntry> table = {
      {"list", "List methods, datasets and profiles, one line each", &make<ListCommand>},
      {"sweep", "Run the command once per cell of the grid (every combination of the --grid values) into OUT/cells/, "
       "then tables over all cells with a column per key; takes every run option", &make<SweepCommand>},
      {"plan", "List the cells of a run or sweep command, one line each (index, methods, dataset, grid cell, seed, "
       "cost class, estimated time on this machine) and the total: the units --cell K, run-cells and slurm run; "
       "methods sharing a base session share a cell",
       &make<PlanCommand>},
      {"run-cells", "Run every cell of a run or sweep command as its own process, --jobs at a time with the threads "
       "split between them (logs in OUT/cell-logs/), then the command's tables", &make<RunCellsCommand>},
      {"slurm", "Write OUT/slurm/array.sbatch (one Slurm array task per cell, SIGTERM-safe, requeued on preemption) "
       "and OUT/slurm/merge.sbatch (the tables, after the array); --submit submits both", &make<SlurmCommand>},
      {"rerun", "Run again exactly the run a result file records (method, dataset, profile, seed, threads, split, "
       "selection, grid cell and every parameter), into --out (default: rerun)", &make<RerunCommand>},
      {"reproduce", "Run one of the paper's tables or figures and write it in the paper's layout (NAME.tex, .md, "
       ".csv, figures/, index.html), our numbers beside the paper's; takes the run options but --methods (default "
       "--out: reproductions/NAME/DATASET)", &make<ReproduceCommand>},
      {"logmel", "Compute log-Mel spectrograms of an HDF5 signal", &make<LogMelCommand>},
      {"report", "Rebuild summary.csv, results.tex, costs.csv, costs.tex and the Markdown tables from result files",
       &make<ReportCommand>},
      {"analyze", "Context-to-class dispersion R per session from result files", &make<AnalyzeCommand>},
      {"check", "Compare result files with stored reference numbers (exit 1 on any drift)", &make<CheckCommand>},
      {"reference", "Write reference numbers from result files (for check)", &make<ReferenceCommand>},
  };
  return table;
}

}  // namespace fscil
