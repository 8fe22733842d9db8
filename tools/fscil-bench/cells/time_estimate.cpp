#include "tools/fscil-bench/cells/time_estimate.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <numeric>
#include <optional>
#include <utility>

#include "core/atomic_file.h"
#include "core/parameter_set.h"
#include "core/stopwatch.h"
#include "protocols/protocol_runner.h"
#include "reports/run_record.h"
#include "tools/fscil-bench/commands/sweep_command.h"
#include "tools/fscil-bench/options/machine_info.h"

namespace fscil {

namespace fs = std::filesystem;

namespace {

constexpr const char* kRatesFile = "step_rates.json";
constexpr double kKeptCpuShare = 0.9;
constexpr int kTimedInferencePasses = 1 + kTimedInferenceRepeats;  // time_inference's warm-up and timed passes
// A run's step against the calibration's median step (ours, docs/profiling.md): base epochs took
// 1.18-1.45 times the calibration on the main job's shape, and 0.94 times on the NS-100 shape,
// whose calibrations ranged 11.7-15.4 ms a sample within a minute on this VM; 1.1 is the mean of
// the two shapes' medians.
constexpr double kRunOverCalibration = 1.1;

double process_cpu_seconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

nlohmann::json read_rates_file(const fs::path& file) {
  std::ifstream in(file);
  if (!in) return nlohmann::json::object();
  nlohmann::json stored = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
  return stored.is_object() ? stored : nlohmann::json::object();
}

std::optional<StepRate> stored_rates(const nlohmann::json& stored, const std::string& key) {
  const auto found = stored.find(key);
  if (found == stored.end() || !found->is_object()) return std::nullopt;
  StepRate rates;
  for (auto [name, value] : {std::pair{"train_seconds_per_sample", &rates.train_seconds_per_sample},
                             std::pair{"infer_seconds_per_sample", &rates.infer_seconds_per_sample},
                             std::pair{"head_step_seconds", &rates.head_step_seconds}}) {
    const auto field = found->find(name);
    if (field == found->end() || !field->is_number() || !(field->get<double>() > 0)) return std::nullopt;
    *value = field->get<double>();
  }
  return rates;
}

}  // namespace

// What the rates depend on: the CPU, the kernels the libraries chose, the threads, the shape and the batch.
std::string step_rates_key(const CommandSizes& sizes) {
  const auto machine = describe_machine();
  return fmt::format("v2 | {} | {} | threads {} | {}x{}x{} | batch {}", machine.at("cpu"), machine.at("kernels"),
                     sizes.threads, sizes.channels, sizes.mel_bins, sizes.frames, sizes.pretraining_batch);
}

StepRate machine_rates(const CommandSizes& sizes) {
  const std::string key = step_rates_key(sizes);
  const fs::path file = sizes.cache_dir.empty() ? fs::path() : fs::path(sizes.cache_dir) / kRatesFile;
  nlohmann::json stored = file.empty() ? nlohmann::json::object() : read_rates_file(file);
  if (const auto rates = stored_rates(stored, key)) return *rates;

  const double cpu_before = process_cpu_seconds();
  const Stopwatch wall;
  const StepRate rates = measure_step_rate(sizes.channels, sizes.mel_bins, sizes.frames, sizes.pretraining_batch);
  // Kept only when its threads had the cores to themselves: a calibration beside other work (or
  // on a host that takes the VM's time) would slow every later plan's estimate.
  const double cpu_share = (process_cpu_seconds() - cpu_before) / (wall.seconds() * std::max(sizes.threads, 1));
  if (!file.empty() && cpu_share >= kKeptCpuShare) {
    stored[key] = {{"train_seconds_per_sample", rates.train_seconds_per_sample},
                   {"infer_seconds_per_sample", rates.infer_seconds_per_sample},
                   {"head_step_seconds", rates.head_step_seconds}};
    std::error_code unwritable;
    fs::create_directories(file.parent_path(), unwritable);
    try {
      write_file_atomically(file, stored.dump(2) + "\n");
    } catch (const std::exception&) {  // a cache that cannot be written costs time, not the plan
    }
  }
  return rates;
}

double run_seconds(const MethodEntry& entry, const ParameterSet& read, const RunSizes& sizes,
                   const StepRate& rates, bool base_trained, std::set<std::string>& trained_stages) {
  double trained = 0, inferred = 0, head_steps = 0;
  std::vector<StageWork> stages;
  if (entry.work) {
    stages = entry.work(read, sizes);
  } else {  // a method compiled outside this tree that declares none
    double epochs = 0;
    for (const auto& key : entry.base_epoch_keys) epochs += static_cast<double>(read.integer(key, 0, ValidRange::at_least(0)));
    stages.push_back({"base", epochs * static_cast<double>(sizes.base_train)});
  }
  for (const StageWork& stage : stages) {
    if (stage.base && base_trained) continue;
    if (entry.shared_stages.count(stage.stage) > 0 && !trained_stages.insert(stage.stage).second) continue;
    trained += stage.trained;
    inferred += stage.inferred;
    head_steps += stage.head_steps;
  }
  // The runner: scored samples embedded once per run or every session, then the timed passes.
  inferred += entry.sessions_keep_embedding
                  ? static_cast<double>(sizes.scored.back())
                  : static_cast<double>(std::accumulate(sizes.scored.begin(), sizes.scored.end(), std::int64_t{0}));
  inferred += kTimedInferencePasses * static_cast<double>(std::min(kTimedInferenceBatch, sizes.scored.back()));
  return kRunOverCalibration * (trained * rates.train_seconds_per_sample + inferred * rates.infer_seconds_per_sample +
                                head_steps * rates.head_step_seconds);
}

void estimate_cells(const RunOptions& options, const std::vector<std::string>& grid, std::vector<BenchCell>& cells,
                    bool one_after_another) {
  one_after_another = one_after_another && options.selection == "last" && uses_stage_cache(options);
  std::map<std::string, std::set<std::string>> trained_stages;  // per grid cell and seed
  std::map<std::map<std::string, std::string>, std::pair<CommandSizes, StepRate>> of_grid_cell;
  for (BenchCell& cell : cells) {
    const RunOptions run = grid.empty() ? options : sweep_cell_options(options, cell.grid);
    auto found = of_grid_cell.find(cell.grid);
    if (found == of_grid_cell.end()) {
      CommandSizes sizes = command_sizes(run);
      const StepRate rates = machine_rates(sizes);
      found = of_grid_cell.emplace(cell.grid, std::pair{std::move(sizes), rates}).first;
    }
    const CommandSizes& sizes = found->second.first;
    const StepRate& rates = found->second.second;
    const RunSizes& run_sizes = sizes.runs.at(cell.seed);
    std::set<std::string> own_stages;
    std::set<std::string>& stages =
        one_after_another ? trained_stages[fmt::format("{}|{}", grid_cell_name(cell.grid), cell.seed)] : own_stages;
    cell.estimated_seconds = 0;
    for (std::size_t i = 0; i < cell.methods.size(); ++i) {
      const MethodEntry& entry = method_entry(cell.methods[i]);
      // A cell's methods share one base (their shared_base_key): the first trains it.
      cell.estimated_seconds +=
          run_seconds(entry, sizes.method_parameters.at(cell.methods[i]), run_sizes, rates, i > 0, stages);
    }
  }
}

}  // namespace fscil
