#include "tools/fscil-bench/cells/time_estimate.h"

#include <fmt/format.h>
#include <iterator>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <numeric>
#include <optional>
#include <utility>

#include "core/atomic_file.h"
#include "core/json_depth.h"
#include "core/parallel_for.h"
#include "core/parameter_set.h"
#include "core/stopwatch.h"
#include "metrics/resource_usage.h"
#include "protocols/protocol_runner.h"
#include "reports/run_record.h"
#include "tools/fscil-bench/commands/sweep_command.h"
#include "tools/fscil-bench/options/machine_info.h"

namespace fscil {

namespace fs = std::filesystem;

namespace {

constexpr const char* kRatesFile = "step_rates.json";
constexpr double kIdleOwnShare = 0.9;     // (ours) of its threads' time, at least
constexpr double kIdleOthersCores = 0.2;  // (ours) other work's cores, less than: an idle VM's own noise is some 0.05
// A run's step against the calibration's median step (ours, docs/profiling.md): base epochs took
// 1.18-1.45 times the calibration on the main job's shape, and 0.94 times on the NS-100 shape,
// whose calibrations ranged 11.7-15.4 ms a sample within a minute on this VM; 1.1 is the mean of
// the two shapes' medians.
constexpr double kRunOverCalibration = 1.1;

nlohmann::json read_rates_file(const fs::path& file) {
  std::ifstream in(file);
  if (!in) return nlohmann::json::object();
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (json_nests_deeper_than(text, kDeepestJson)) return nlohmann::json::object();  // not ours: measured over
  nlohmann::json stored = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  return stored.is_object() ? stored : nlohmann::json::object();
}

std::optional<StepRate> stored_rates(const nlohmann::json& entry) {
  if (!entry.is_object()) return std::nullopt;
  StepRate rates;
  for (auto [name, value] : {std::pair{"train_seconds_per_sample", &rates.train_seconds_per_sample},
                             std::pair{"infer_seconds_per_sample", &rates.infer_seconds_per_sample},
                             std::pair{"head_step_seconds", &rates.head_step_seconds}}) {
    const auto field = entry.find(name);
    if (field == entry.end() || !field->is_number() || !(field->get<double>() > 0)) return std::nullopt;
    *value = field->get<double>();
  }
  return rates;
}

std::string rates_text(const StepRate& rates) {
  return fmt::format("{:.2f} ms a sample trained, {:.2f} inferred, {:.2f} ms a head step",
                     1e3 * rates.train_seconds_per_sample, 1e3 * rates.infer_seconds_per_sample,
                     1e3 * rates.head_step_seconds);
}

std::string utc_now() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  std::array<char, 32> text{};
  std::strftime(text.data(), text.size(), "%Y-%m-%d %H:%M UTC", &utc);
  return text.data();
}

std::string precision_name(Precision precision) { return precision == Precision::bf16 ? "bf16" : "fp32"; }

}  // namespace

double CalibrationLoad::others_cores() const {
  if (machine_cpu_seconds <= 0 || wall_seconds <= 0) return 0;
  return std::max(0.0, (machine_cpu_seconds - own_cpu_seconds) / wall_seconds);
}

double CalibrationLoad::contended_cores() const {
  return std::max(0.0, others_cores() - std::max(0, cores - threads));
}

double CalibrationLoad::own_share() const {
  return wall_seconds > 0 ? own_cpu_seconds / (wall_seconds * std::clamp(threads, 1, std::max(cores, 1))) : 1;
}

bool CalibrationLoad::idle() const { return own_share() >= kIdleOwnShare && contended_cores() < kIdleOthersCores; }

// What the rates depend on: the CPU, the kernels the libraries chose, the threads, the precision
// (fp32 keys keep the form they had before bf16 existed), the shape and the batch.
std::string step_rates_key(const CommandSizes& sizes) {
  const auto machine = describe_machine();
  return fmt::format("v2 | {} | {} | threads {}{} | {}x{}x{} | batch {}", machine.at("cpu"), machine.at("kernels"),
                     sizes.threads, sizes.precision == Precision::fp32 ? "" : " | " + precision_name(sizes.precision),
                     sizes.channels, sizes.mel_bins, sizes.frames, sizes.pretraining_batch);
}

std::optional<Calibration> stored_machine_rates(const CommandSizes& sizes) {
  if (sizes.cache_dir.empty()) return std::nullopt;
  const fs::path file = fs::path(sizes.cache_dir) / kRatesFile;
  const nlohmann::json stored = read_rates_file(file);
  const auto entry = stored.find(step_rates_key(sizes));
  if (entry == stored.end()) return std::nullopt;
  const auto rates = stored_rates(*entry);
  if (!rates) return std::nullopt;
  const std::string when = entry->value("measured", std::string("before dates were kept"));
  return Calibration{sizes, *rates, true, fmt::format("rates stored in {} (measured {}, the machine idle): {}",
                                                      file.string(), when, rates_text(*rates))};
}

Calibration machine_rates(const CommandSizes& sizes) {
  if (std::optional<Calibration> stored = stored_machine_rates(sizes)) return *stored;
  const std::string key = step_rates_key(sizes);
  const fs::path file = sizes.cache_dir.empty() ? fs::path() : fs::path(sizes.cache_dir) / kRatesFile;
  nlohmann::json stored = file.empty() ? nlohmann::json::object() : read_rates_file(file);

  const CpuTimes before = cpu_times_now();
  const Stopwatch wall;
  const StepRate rates = measure_step_rate(sizes.channels, sizes.mel_bins, sizes.frames, sizes.pretraining_batch,
                                           1.0, sizes.precision);
  const CpuTimes after = cpu_times_now();
  const CalibrationLoad load{wall.seconds(), after.process_seconds - before.process_seconds,
                             after.machine_seconds - before.machine_seconds, std::max(sizes.threads, 1),
                             thread_count(0)};
  const std::string others =
      load.machine_cpu_seconds > 0 ? fmt::format("other work held {:.2f} of {} cores", load.others_cores(), load.cores)
                                   : std::string("other work unknown: /proc/stat unread");
  if (!load.idle()) {
    // Kept, it would stand for this machine's speed in every later plan.
    return {sizes, rates, false,
            fmt::format("rates measured now UNDER LOAD ({}; the calibration's {} threads had {:.0f}% of their time): "
                        "{}; the estimates are this machine's as loaded now, not idle, and the rates are not stored: "
                        "plan again on an idle machine",
                        others, load.threads, 100 * load.own_share(), rates_text(rates))};
  }
  std::string basis = fmt::format("rates measured now, the machine idle ({}): {}", others, rates_text(rates));
  if (!file.empty()) {
    stored[key] = {{"train_seconds_per_sample", rates.train_seconds_per_sample},
                   {"infer_seconds_per_sample", rates.infer_seconds_per_sample},
                   {"head_step_seconds", rates.head_step_seconds},
                   {"measured", utc_now()}};
    std::error_code unwritable;
    fs::create_directories(file.parent_path(), unwritable);
    try {
      write_file_atomically(file, stored.dump(2) + "\n");
      basis += fmt::format("; stored in {}", file.string());
    } catch (const std::exception&) {  // a cache that cannot be written costs time, not the plan
    }
  }
  return {sizes, rates, true, basis};
}

std::string bf16_note(const Calibration& own) {
  if (!bf16_is_native()) {
    return fmt::format("--precision bf16: emulated on this CPU (oneDNN's kernels {}: no AVX512-BF16 or AMX), slower "
                       "than fp32",
                       numeric_kernels());
  }
  CommandSizes other_sizes = own.sizes;
  other_sizes.precision = own.sizes.precision == Precision::bf16 ? Precision::fp32 : Precision::bf16;
  const Calibration other = machine_rates(other_sizes);
  const Calibration& fp32 = own.sizes.precision == Precision::fp32 ? own : other;
  const Calibration& bf16 = own.sizes.precision == Precision::bf16 ? own : other;
  const double train = fp32.rates.train_seconds_per_sample / bf16.rates.train_seconds_per_sample;
  const double infer = fp32.rates.infer_seconds_per_sample / bf16.rates.infer_seconds_per_sample;
  return fmt::format("--precision bf16 on this CPU: training step {:.2f}x, inference {:.2f}x fp32's speed on this "
                     "command's shape{} (its numbers differ from fp32's: docs/profiling.md, \"bfloat16\")",
                     train, infer, fp32.idle && bf16.idle ? "" : ", measured under load");
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
  // A method counts its sessions' work as if each added classes; a removing session trains nothing.
  const int incremental = sizes.sessions - 1;
  const double training_share =
      incremental > 0 ? static_cast<double>(incremental - sizes.removing_sessions) / incremental : 1.0;
  for (const StageWork& stage : stages) {
    if (stage.base && base_trained) continue;
    if (entry.shared_stages.count(stage.stage) > 0 && !trained_stages.insert(stage.stage).second) continue;
    const double share = stage.base ? 1.0 : training_share;
    trained += share * stage.trained;
    inferred += share * stage.inferred;
    head_steps += share * stage.head_steps;
  }
  // The runner: scored samples embedded once per run or every session, then the timed passes.
  inferred += entry.sessions_keep_embedding
                  ? static_cast<double>(sizes.scored.back())
                  : static_cast<double>(std::accumulate(sizes.scored.begin(), sizes.scored.end(), std::int64_t{0}));
  inferred += sizes.timed_inference_passes * static_cast<double>(std::min(kTimedInferenceBatch, sizes.scored.back()));
  return kRunOverCalibration * (trained * rates.train_seconds_per_sample + inferred * rates.infer_seconds_per_sample +
                                head_steps * rates.head_step_seconds);
}

std::vector<Calibration> estimate_cells(const RunOptions& options, const std::vector<std::string>& grid,
                                        std::vector<BenchCell>& cells, bool one_after_another) {
  one_after_another = one_after_another && options.selection == "last" && uses_stage_cache(options);
  std::map<std::string, std::set<std::string>> trained_stages;  // per grid cell and seed
  std::map<GridCell, std::pair<CommandSizes, StepRate>> of_grid_cell;
  std::vector<Calibration> calibrations;
  for (BenchCell& cell : cells) {
    const RunOptions run = grid.empty() ? options : sweep_cell_options(options, cell.grid);
    auto found = of_grid_cell.find(cell.grid);
    if (found == of_grid_cell.end()) {
      CommandSizes sizes = command_sizes(run);
      Calibration calibration = machine_rates(sizes);
      const StepRate rates = calibration.rates;
      const bool new_basis = std::none_of(calibrations.begin(), calibrations.end(),
                                          [&](const Calibration& seen) { return seen.basis == calibration.basis; });
      if (new_basis) calibrations.push_back(std::move(calibration));
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
  return calibrations;
}

}  // namespace fscil
