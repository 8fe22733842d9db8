#pragma once
#include <set>
#include <optional>
#include <string>
#include <vector>

#include "methods/common/step_rate.h"
#include "methods/method_registry.h"
#include "tools/fscil-bench/cells/bench_cells.h"
#include "tools/fscil-bench/commands/run_command.h"

namespace fscil {

class ParameterSet;

// How much of the machine other work held while a calibration ran, from the CPU times read before
// and after it (metrics/resource_usage.h).
struct CalibrationLoad {
  double wall_seconds = 0;
  double own_cpu_seconds = 0;      // the calibrating process's, every thread
  double machine_cpu_seconds = 0;  // every core's busy time, ours included; 0 where unknown
  int threads = 1;                 // the calibration's
  int cores = 1;                   // the machine's
  // Cores other processes (and a host's steal) held on average meanwhile; 0 where unknown.
  double others_cores() const;
  // Of those, the ones the calibration's threads needed: other work on cores its threads leave
  // free costs it nothing.
  double contended_cores() const;
  // The share of its threads' time the calibration had (threads beyond the cores counted as cores).
  double own_share() const;
  // It had the cores it needs to itself: its threads had at least 90% of their time and other
  // work took less than a fifth of a core from them. OpenMP threads spin while they wait for one
  // another, so a calibration slowed down by a neighbour can still show its threads busy: the
  // machine's busy time is what tells.
  bool idle() const;
};

// The rates an estimate uses, and the one line `plan` prints about them: where they come from
// and whether the machine was idle when they were measured.
struct Calibration {
  CommandSizes sizes;  // what it was measured for
  StepRate rates;
  bool idle = false;
  std::string basis;
};

// This machine's rates for the command (methods/common/step_rate.h): from `step_rates.json` in
// its cache folder when that holds this CPU, kernels, threads, precision, shape and batch;
// otherwise measured now (seconds; some 20 on the audio shapes) and stored there, unless other
// work held the cores meanwhile (CalibrationLoad::idle: such a calibration estimates the machine
// as loaded then, is used for this plan only and says so), under --no-cache, or where the folder
// cannot be written. An entry that does not read is measured over.
Calibration machine_rates(const CommandSizes& sizes);
// Those rates where `step_rates.json` holds them; nothing is measured.
std::optional<Calibration> stored_machine_rates(const CommandSizes& sizes);
// The entry of `step_rates.json` that holds them; its leading version changes whenever what
// measure_step_rate() times changes.
std::string step_rates_key(const CommandSizes& sizes);

// Whether --precision bf16 would pay here, for `plan` to say: on a CPU whose kernels compute
// bf16 natively (AVX512-BF16 or AMX) the training step and inference pass of `own`'s shape in
// bf16 against fp32 (the other precision from the rate cache, or measured once); elsewhere, that
// bf16 is emulated there.
std::string bf16_note(const Calibration& own);

// One run's seconds at `rates`: its stages (MethodEntry::work) and what the runner does for every
// method: embedding the scored samples (once per run where the entry's sessions keep the
// embedding, every session otherwise) and the eight timed inference passes. A stage of the base
// session is left out when `base_trained` (a method of its cell with the same shared_base_key
// trained it); a stage the entry names in shared_stages is left out when `trained_stages` holds
// it, and added there otherwise (a later cell of the same seed continues from it). A stage after
// the base session counts the adding sessions' share of it: a removing session trains nothing.
double run_seconds(const MethodEntry& entry, const ParameterSet& read, const RunSizes& sizes, const StepRate& rates,
                   bool base_trained, std::set<std::string>& trained_stages);

// Fills every cell's estimated_seconds on this machine; prepares the dataset as the command would
// (from the cache, or built and cached). `one_after_another`: cells run in plan order in one
// place, so a later cell continues from a shared stage an earlier one trained (a whole command;
// cells run apart share it through the stage cache); otherwise (Slurm tasks at once), under a
// --selection other than last (no stage is shared then), --no-stage-cache or --no-cache, every
// cell trains its own.
// Returns every calibration it used, once.
std::vector<Calibration> estimate_cells(const RunOptions& options, const std::vector<std::string>& grid,
                                        std::vector<BenchCell>& cells, bool one_after_another = true);

}  // namespace fscil
