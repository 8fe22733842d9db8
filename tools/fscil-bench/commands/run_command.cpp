#include "tools/fscil-bench/options/dataset_defaults.h"
#include "tools/fscil-bench/commands/run_command.h"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <algorithm>
#include <cstdlib>
#include <iostream>
#include <map>
#include <memory>
#include <numeric>
#include <optional>
#include <set>

#include "datasets/dataset_catalog.h"
#include "datasets/hdf5_file.h"
#include "datasets/segment_cache.h"
#include "methods/common/supervised_training.h"
#include "methods/common/torch_random_state.h"
#include "methods/method_registry.h"
#include "metrics/convergence.h"
#include "metrics/resource_usage.h"
#include "protocols/profiles.h"
#include "core/error.h"
#include "core/file_lock.h"
#include "tools/fscil-bench/options/run_option_table.h"
#include "protocols/protocol_runner.h"
#include "protocols/run_checkpoint.h"
#include "protocols/stage_progress_files.h"
#include "protocols/saved_model.h"
#include "protocols/shared_stages.h"
#include "protocols/stage_cache.h"
#include "core/stop_request.h"
#include "core/shown_text.h"
#include "protocols/session_schedule.h"
#include "reports/comparable_runs.h"
#include "tools/fscil-bench/options/byte_size.h"
#include "tools/fscil-bench/options/machine_info.h"
#include "tools/fscil-bench/cells/out_folder_lock.h"
#include "tools/fscil-bench/cells/time_estimate.h"
#include "tools/fscil-bench/commands/report_writer.h"
#include "tools/fscil-bench/options/seed_list.h"
#include "core/number_text.h"
#include "core/parallel_for.h"

namespace fscil {

namespace fs = std::filesystem;

namespace {

fs::path default_cache_dir() {
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg != nullptr && *xdg != '\0') return fs::path(xdg) / "fscil-bench";
  if (const char* home = std::getenv("HOME"); home != nullptr && *home != '\0') return fs::path(home) / ".cache" / "fscil-bench";
  return fs::temp_directory_path() / "fscil-bench-cache";
}

// A cached base's outcome carries the peak memory of the run that trained it under this
// diagnostic; it is taken out before the outcome is used.
constexpr const char* kCachedPeakKey = "stage_cache_peak_resident_bytes";

fs::path cache_folder(const RunOptions& options) {
  return options.cache_dir.empty() ? default_cache_dir() : fs::path(options.cache_dir);
}

ParameterSet base_parameters(const RunOptions& options) {
  ParameterSet params;
  apply_dataset_defaults(options.dataset, params);
  apply_profile(options.profile, params);
  params.set("split_mode", options.split_mode);
  params.set("class_order", options.class_order);
  apply_assignments(options, params);
  return params;
}

// A --set or --grid key that no dataset, protocol or method reads is a typo: refuse it before
// training, named by the option that gave it.
void reject_unread_keys(const ParameterSet& params, const std::vector<const ParameterSet*>& readers,
                        const GridCell& grid) {
  ParameterSet combined = params;
  for (const auto* reader : readers) combined.mark_read(reader->read_keys());
  const auto unread = combined.unread_keys();
  if (!unread.empty()) {
    const bool swept = grid_value(grid, *unread.begin()) != nullptr;
    throw ProtocolError(fmt::format("{} {}: no dataset, protocol or method of this run reads it",
                                    swept ? "--grid" : "--set", fmt::join(unread, ", ")));
  }
}

// A run's parameters that name it: all but base_training, how the base was obtained, not what it is.
std::map<std::string, std::string> identity_parameters(const RunRecord& record) {
  std::map<std::string, std::string> parameters = record.parameters;
  parameters.erase("base_training");
  return parameters;
}

// Everything that shapes a run's numbers; a checkpoint or result file of another run is refused.
std::string identity_of(const RunRecord& record) {
  const std::map<std::string, std::string> parameters = identity_parameters(record);
  return fmt::format("method={} dataset={} data={} seed={} threads={} profile={} scored={} selection={} cell={} "
                     "parameters={}", record.method, record.dataset, record.dataset_key, record.seed, record.threads,
                     record.profile, record.evaluated_on, record.selection, grid_cell_name(record.grid),
                     stable_hash(parameters));
}

// What makes `earlier` another run than `now` (identity_of's fields), for a refusal that says
// which option to change: "temperature: 16 there, 8 here; ...".
std::string differences(const RunRecord& earlier, const RunRecord& now) {
  std::vector<std::string> found;
  const auto compare = [&](const std::string& what, const std::string& there, const std::string& here) {
    if (there != here) found.push_back(fmt::format("{}: {} there, {} here", what, shown_text(there), shown_text(here)));
  };
  compare("method", earlier.method, now.method);
  compare("dataset", earlier.dataset, now.dataset);
  compare("data", earlier.dataset_key, now.dataset_key);
  compare("seed", std::to_string(earlier.seed), std::to_string(now.seed));
  compare("threads", std::to_string(earlier.threads), std::to_string(now.threads));
  compare("profile", earlier.profile, now.profile);
  compare("scored on", earlier.evaluated_on, now.evaluated_on);
  compare("selection", earlier.selection, now.selection);
  compare("grid cell", grid_cell_name(earlier.grid), grid_cell_name(now.grid));
  const auto there = identity_parameters(earlier), here = identity_parameters(now);
  std::set<std::string> keys;
  for (const auto* parameters : {&there, &here}) {
    for (const auto& [key, value] : *parameters) keys.insert(key);
  }
  const auto value_in = [](const std::map<std::string, std::string>& parameters, const std::string& key) {
    const auto found_value = parameters.find(key);
    return found_value == parameters.end() ? std::string("(not set)") : found_value->second;
  };
  for (const auto& key : keys) compare(key, value_in(there, key), value_in(here, key));
  if (found.empty()) return identity_of(earlier);  // identity_of reads no other field; kept safe all the same
  constexpr std::size_t kShown = 5;
  const std::size_t more = found.size() > kShown ? found.size() - kShown : 0;
  found.resize(std::min(found.size(), kShown));
  return fmt::format("{}{}", fmt::join(found, "; "), more > 0 ? fmt::format("; and {} more", more) : "");
}

fs::path checkpoint_path(const fs::path& out, const std::string& method, const std::string& dataset,
                         std::uint64_t seed) {
  RunRecord name;
  name.method = method;
  name.dataset = dataset;
  name.seed = seed;
  return out / "checkpoints" / fs::path(run_record_file_name(name)).replace_extension(".ckpt");
}

bool holds_results(const fs::path& out) {
  if (!fs::is_directory(out / "results")) return false;
  for (const auto& entry : fs::directory_iterator(out / "results")) {
    if (entry.path().extension() == ".json") return true;
  }
  return false;
}

// With --resume: the runs already finished in `out`, which must be runs of this command.
std::vector<RunRecord> finished_runs(const RunOptions& options) {
  if (!options.resume || !holds_results(options.out)) return {};  // none stopped before its first run finished
  return load_run_records(options.out);
}

// A new command may add runs to an --out only where they can share its tables (same data,
// profile, split, threads and protocol; per method, the same parameters), and never a run the
// folder holds already (continuing is --resume's). A cell is checked even as it continues: its
// folder holds the other cells' runs.
void require_room_for(const std::vector<RunRecord>& planned, const std::vector<std::uint64_t>& seeds,
                      const RunOptions& options) {
  if ((options.resume && options.cell < 0) || !holds_results(options.out)) return;
  const std::vector<RunRecord> existing = load_run_records(options.out);
  for (const auto& run : planned) {
    for (const auto& earlier : existing) {
      if (const std::string why = incomparability(earlier, run); !why.empty()) {
        throw ProtocolError(fmt::format("--out {}: {} holds a run that cannot share a table with this one ({}); "
                                        "write to another --out", options.out, earlier.source, why));
      }
      // Refused before any work: its result file is an input of this command, which must not replace it.
      const bool same_run = earlier.method == run.method && earlier.dataset == run.dataset &&
                            std::count(seeds.begin(), seeds.end(), earlier.seed) > 0 &&
                            grid_cell_name(earlier.grid) == grid_cell_name(run.grid);
      if (!options.resume && same_run) {
        throw ProtocolError(fmt::format("--out {}: {} holds a run of this command already ({}, seed {}); --resume {} "
                                        "keeps it and runs what is missing, or write to another --out", options.out,
                                        earlier.source, run.method, earlier.seed, options.out));
      }
    }
  }
}

// The sessions --save-embeddings names, as a test of a session number (of `sessions`; 0 before the
// sessions are drawn, which checks the list's form alone).
std::function<bool(int)> sessions_to_save(const std::string& text, int sessions) {
  if (text.empty()) return {};
  if (text == "all") return [](int) { return true; };
  if (text == "last") return [sessions](int session) { return session == sessions - 1; };
  std::set<int> chosen;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    const std::string field = text.substr(start, comma - start);
    const auto session = parse_number<int>(field);
    if (!session || *session < 0 || (sessions > 0 && *session >= sessions)) {
      throw CliError(fmt::format("--save-embeddings {}: expected last, all or session numbers from 0{}, "
                                 "comma-separated", text,
                                 sessions > 0 ? fmt::format(" to {}", sessions - 1) : std::string()));
    }
    if (!chosen.insert(*session).second) {
      throw CliError(fmt::format("--save-embeddings {}: session {} given twice; name each session once", text,
                                 *session));
    }
    start = comma + 1;
  }
  return [chosen](int session) { return chosen.count(session) > 0; };
}

// The embeddings --save-embeddings keeps of one run, written as one HDF5 file.
struct SavedEmbeddings {
  std::map<int, FloatArray> embeddings;
  std::map<int, std::vector<std::int32_t>> labels;

  void write(const fs::path& path, int base_classes) const {
    Hdf5Contents contents;
    for (const auto& [session, array] : embeddings) {
      contents.floats[fmt::format("session_{}_embeddings", session)] = &array;
      contents.integers[fmt::format("session_{}_labels", session)] = labels.at(session);
    }
    contents.integers["base_classes"] = {base_classes};
    for (const auto& [session, array] : embeddings) contents.integers["sessions"].push_back(session);
    write_hdf5_atomically(path, contents);
  }
};

// Where a run keeps the embeddings it has saved so far, beside its checkpoint: a resumed run
// cannot embed again the sessions before the one it continues from.
fs::path embeddings_so_far_path(const fs::path& checkpoint_file) {
  return fs::path(checkpoint_file).replace_extension(".embeddings.h5");
}

// A resumed run's saved embeddings of the sessions before the last one its checkpoint finished
// (that one run_sessions hands over again); ProtocolError when one --save-embeddings asks for was
// not kept before the interruption.
SavedEmbeddings embeddings_before_the_stop(const std::function<bool(int)>& save_session,
                                           const std::vector<SessionOutcome>& finished, const fs::path& checkpoint_file) {
  SavedEmbeddings kept;
  const fs::path file = embeddings_so_far_path(checkpoint_file);
  std::vector<std::int32_t> sessions;
  if (finished.size() > 1 && fs::exists(file)) sessions = read_hdf5_integers(file, "sessions");
  for (int session = 0; session + 1 < static_cast<int>(finished.size()); ++session) {
    if (!save_session(session)) continue;
    if (std::find(sessions.begin(), sessions.end(), session) == sessions.end()) {
      throw ProtocolError(fmt::format("{}: the embeddings of session {}, which --save-embeddings asks for, were not "
                                      "kept before the interruption (the interrupted command did not save them); "
                                      "run this method again without --resume, or leave session {} out",
                                      checkpoint_file.string(), session, session));
    }
    kept.embeddings[session] = read_hdf5_floats(file, fmt::format("session_{}_embeddings", session), 2);
    kept.labels[session] = read_hdf5_integers(file, fmt::format("session_{}_labels", session));
  }
  return kept;
}

// What every run of the command shares, fixed before the first one trains: its methods and seeds,
// the values that shape a run, the prepared data and each seed's sessions.
struct CommandPlan {
  std::vector<std::string> method_names;
  std::vector<std::uint64_t> seeds;
  int threads = 0;
  ParameterSet params;                     // dataset defaults, profile and --set: what each run starts from
  std::vector<ParameterSet> method_params;  // what each method read of them
  ParameterSet protocol_params, dataset_params;
  bool recompute_activations = false;
  Precision precision = Precision::fp32;
  EvaluationSplit evaluation{};
  EpochSelection selection{};
  std::int64_t memory_limit = 0;
  std::shared_ptr<MemoryBudget> memory_budget;  // one for the command: a handed-on base keeps its encoder
  PreparedDataset dataset;
  InputShape input{};
  std::vector<SessionSchedule> schedules;  // one per seed
  std::function<bool(int)> save_session;   // --save-embeddings
  // The values runs of one table must share (RunRecord::protocol_parameters).
  std::map<std::string, std::string> protocol_parameters;
  double stage_progress_interval = 0;  // seconds between two keepings of a base stage's progress
};

Precision chosen_precision(const RunOptions& options) {
  require_precision_name(options.precision);
  return options.precision == "bf16" ? Precision::bf16 : Precision::fp32;
}

void check_run_options(const RunOptions& options) {
  if (options.out.empty()) throw ProtocolError("--out '': expected a folder for the results");
  require_selection_name(options.selection);
  chosen_precision(options);
  sessions_to_save(options.save_embeddings, 0);  // its form before any work, its numbers once sessions are drawn
}

// Each seed's session schedule; refuses, before any training, a split the data lacks.
std::vector<SessionSchedule> session_schedules(const RunOptions& options, CommandPlan& plan, SplitMode split_mode) {
  std::vector<SessionSchedule> schedules;
  const auto& description = plan.dataset.description;
  for (std::uint64_t seed : plan.seeds) {
    const SessionPlan session_plan = make_session_plan(static_cast<int>(description.class_names.size()),
                                                       description.sessions, plan.protocol_params, seed);
    try {
      schedules.push_back(build_session_schedule(plan.dataset.segments, description.class_names, session_plan,
                                                 split_mode, seed));
      schedules.back().scored_segments(plan.evaluation);
    } catch (const ProtocolError& error) {
      const std::string where = options.data_root.empty() ? "" : fmt::format(" in {}", options.data_root);
      throw ProtocolError(fmt::format("dataset {}{}, {}-way {}-shot: {}", options.dataset, where, session_plan.way,
                                      session_plan.shot, error.what()));
    }
  }
  return schedules;
}

// Step 1: every option, method and value checked, the data prepared, the sessions drawn.
CommandPlan plan_command(const RunOptions& options, ProgressReporter& progress) {
  check_run_options(options);
  CommandPlan plan;
  plan.method_names = resolve_method_names(options.methods);
  plan.seeds = parse_seed_list(options.seeds);
  plan.threads = configure_threads(options.threads);
  plan.params = base_parameters(options);
  // Methods read their hyper-parameters on construction, so a bad value fails here, early.
  for (const auto& name : plan.method_names) {
    plan.method_params.push_back(plan.params);
    create_method(name, plan.method_params.back());
  }
  plan.protocol_params = plan.params;
  const SplitMode split_mode = parse_split_mode(plan.protocol_params.text("split_mode", "recording"));
  // Activation recomputation: less memory, more time, the same numbers (ResNet18Options).
  plan.recompute_activations = plan.protocol_params.choice("recompute", "none", {"none", "stages"}) == "stages";
  plan.precision = chosen_precision(options);
  plan.stage_progress_interval = stage_progress_interval();
  plan.evaluation = parse_evaluation_split(options.evaluate_on);
  plan.selection = options.selection == "validation"    ? EpochSelection::validation
                   : options.selection == "test-oracle" ? EpochSelection::test_oracle
                                                        : EpochSelection::last;
  plan.memory_limit = options.max_memory.empty() ? 0 : parse_byte_size(options.max_memory, "--max-memory");
  if (plan.memory_limit > 0) {
    plan.memory_budget = std::make_shared<MemoryBudget>(plan.memory_limit);
    return_large_blocks_to_the_kernel();
  }

  DatasetRequest request;
  request.data_root = options.data_root;
  request.cache_dir = options.no_cache ? fs::path() : cache_folder(options);
  request.threads = plan.threads;
  request.features = parse_feature_storage(options.features);
  plan.dataset_params = plan.params;
  require_dataset_name(options.dataset);  // before a line says it is being prepared
  progress.stage(fmt::format("preparing dataset {}", options.dataset));
  Stopwatch dataset_clock;
  plan.dataset = prepare_dataset(options.dataset, request, plan.dataset_params, std::cerr);
  plan.input = input_shape_of(plan.dataset);
  progress.note(fmt::format("{} segments of shape {}x{}x{} ready in {:.1f}s", plan.dataset.segments.count(),
                            plan.input.channels, plan.input.mel_bins, plan.input.frames, dataset_clock.seconds()));

  plan.schedules = session_schedules(options, plan, split_mode);
  if (plan.schedules.front().plan.removal != ClassRemoval::none && plan.selection == EpochSelection::test_oracle) {
    // The methods' epoch scoring does not drop removed classes' rows as the runner's does.
    throw ProtocolError("--selection test-oracle cannot be combined with removal=fciac");
  }
  if (const std::string removal = describe_removal(plan.schedules.front().plan); !removal.empty()) progress.note(removal);
  plan.save_session = sessions_to_save(options.save_embeddings, plan.schedules.front().plan.sessions);
  std::vector<const ParameterSet*> readers = {&plan.protocol_params, &plan.dataset_params};
  for (const auto& method_param : plan.method_params) readers.push_back(&method_param);
  reject_unread_keys(plan.params, readers, options.grid);

  plan.protocol_parameters = plan.dataset_params.used();
  for (const auto& [key, value] : plan.protocol_params.used()) plan.protocol_parameters[key] = value;
  // Like recompute: the same numbers, another peak. Named only when given, so runs without it
  // keep their identity.
  if (plan.memory_limit > 0) plan.protocol_parameters["max_memory"] = std::to_string(plan.memory_limit);
  // Other numbers than fp32's: never one table with fp32 runs (named only when given, like max_memory).
  if (plan.precision != Precision::fp32) plan.protocol_parameters["precision"] = options.precision;
  // Chosen on test or on validation: never one table with runs of the last epoch (named only when
  // given, like max_memory).
  if (options.selection != "last") plan.protocol_parameters["selection"] = options.selection;
  return plan;
}

// What a run of the command is before it trains: its identity, and the start of its record.
RunRecord planned_run(const RunOptions& options, const CommandPlan& plan, const std::string& method,
                      const ParameterSet& method_parameters, std::uint64_t seed) {
  RunRecord run;
  run.method = method;
  run.dataset = options.dataset;
  run.profile = options.profile;
  run.seed = seed;
  run.threads = plan.threads;
  run.evaluated_on = to_string(plan.evaluation);
  run.selection = options.selection;
  run.grid = options.grid;
  run.parameters = method_parameters.used();
  for (const auto& [key, value] : plan.protocol_parameters) run.parameters[key] = value;
  run.protocol_parameters = plan.protocol_parameters;
  run.dataset_key = plan.dataset.cache_key;
  return run;
}

// rerun FILE runs the run the file records, every value from the file.
void require_every_value_recorded(const RunRecord& planned, const RunOptions& options) {
  for (const auto& [key, value] : identity_parameters(planned)) {
    if (options.rerun_parameters.count(key) == 0) {
      throw ReportError(fmt::format("{}: field 'parameters.{}' missing, expected every value the run reads (every "
                                    "result file names them all; one of an older fscil-bench lacks those added "
                                    "since: rerun it with the binary of its git_commit)", options.rerun_of,
                                    shown_text(key)));
    }
  }
}

// Step 2: --out may take these runs (they can share its tables), and this command holds it.
OutFolderLock claim_out_folder(const RunOptions& options, const CommandPlan& plan) {
  std::vector<RunRecord> planned;
  for (std::size_t m = 0; m < plan.method_names.size(); ++m) {
    planned.push_back(planned_run(options, plan, plan.method_names[m], plan.method_params[m], plan.seeds.front()));
  }
  if (!options.rerun_of.empty()) require_every_value_recorded(planned.front(), options);
  require_room_for(planned, plan.seeds, options);
  std::vector<std::string> cell_runs;  // what a --cell command holds of the folder
  for (const auto& method : plan.method_names) {
    for (std::uint64_t seed : plan.seeds) {
      cell_runs.push_back(checkpoint_path("", method, options.dataset, seed).stem().string());
    }
  }
  // Resuming with other --methods or --seeds than the interrupted command would run what it did
  // not and leave its interrupted run behind.
  const fs::path checkpoints = fs::path(options.out) / "checkpoints";
  if (options.resume && options.cell < 0 && fs::is_directory(checkpoints)) {
    for (const auto& entry : fs::directory_iterator(checkpoints)) {
      // A run stopped within its base stage has only its progress (stage_progress_files.h); one
      // stopped just after its base session's checkpoint may have both, named by the checkpoint.
      const fs::path& file = entry.path();
      if (file.extension() != ".ckpt" && file.extension() != ".progress") continue;
      if (file.extension() == ".progress" && fs::exists(fs::path(file).replace_extension(".ckpt"))) continue;
      if (std::find(cell_runs.begin(), cell_runs.end(), entry.path().stem().string()) == cell_runs.end()) {
        throw ProtocolError(fmt::format("--resume {}: {} is the checkpoint of a run this command does not make; "
                                        "resume with the --methods and --seeds of the interrupted command",
                                        options.out, entry.path().string()));
      }
    }
  }
  return options.cell < 0 ? OutFolderLock(options.out) : OutFolderLock(options.out, cell_runs);
}

// A base session trained or inherited by one run, kept for the next method sharing it.
struct TrainedBase {
  std::unique_ptr<Method> method;
  std::string trained_by;
  double seconds = 0;
  std::map<std::string, double> diagnostics;
  std::vector<EpochLog> training_log;
};

// What the runs of the command share besides the plan: the machine, the stage cache, the runs
// --resume keeps, and the bases trained so far (per shared base key and seed).
struct CommandRuns {
  std::map<std::string, std::string> machine;
  std::string commit;
  std::string code;  // the executable's digest; empty when the stage cache is not in use
  StageCache stage_cache;
  // What else shapes a base besides the method's values: the front end and dataset knobs (the
  // dataset key covers segments only) and the run-wide recompute (same numbers, another peak).
  std::map<std::string, std::string> run_values;
  std::vector<RunRecord> finished;
  std::map<std::pair<std::string, std::uint64_t>, TrainedBase> trained_bases;
  std::vector<RunRecord> records;
  SharedStages shared_stages;  // stages of bases that methods share (MethodEntry::shared_stages)

  bool stage_caching() const { return !code.empty(); }
};

CommandRuns start_runs(const RunOptions& options, const CommandPlan& plan) {
  CommandRuns runs{describe_machine(), source_commit(), {}, StageCache(cache_folder(options) / "stages"), {}, {}, {}, {}, SharedStages()};
  // The executable is read only when the stage cache is in use.
  if (uses_stage_cache(options)) runs.code = code_digest(runs.machine);
  if (runs.stage_caching()) runs.shared_stages = SharedStages(runs.stage_cache);
  runs.run_values = plan.dataset_params.used();
  runs.run_values["front_end"] = plan.dataset.description.front_end.describe();
  runs.run_values["recompute"] = plan.recompute_activations ? "stages" : "none";
  if (plan.memory_limit > 0) runs.run_values["max_memory"] = std::to_string(plan.memory_limit);
  if (plan.precision != Precision::fp32) runs.run_values["precision"] = options.precision;
  runs.finished = finished_runs(options);
  return runs;
}

// One (method, seed) run while it runs: its method and context, where it started its base.
struct RunInProgress {
  std::string method_name;
  std::uint64_t seed = 0;
  std::size_t schedule = 0;  // index of the seed
  ParameterSet params;
  std::unique_ptr<Method> method;
  RunRecord record;
  std::string identity;
  fs::path checkpoint_file;
  RunContext context;
  std::string base_key;       // MethodEntry::shared_base_key
  std::string base_identity;  // the stage cache's key of its base; empty without the cache
  std::unique_ptr<RunStages> stages;  // RunContext::stages
  std::unique_ptr<StageProgressFiles> stage_progress;  // RunContext::stage_progress
  std::optional<InheritedBase> inherited_base;
  std::string base_trained_by;
  bool base_from_cache = false;
  std::optional<FileLock> base_claim;  // StageCache::claim while it trains a base the cache lacks
  std::int64_t resident_at_start = 0;  // the process's resident memory as the run began
  std::int64_t base_peak_bytes = 0;    // what the run that trained a cached base added (run_peak_bytes)
  SessionCheckpoints checkpoints;
  double seconds_before = 0;
  Stopwatch clock;
};

// Everything that shapes the run's base session, or a stage of it, filed as `trained`: the run's
// values without those read only after it (`left_out`, and the sessions' own).
std::string trained_identity(const RunOptions& options, const CommandPlan& plan, const CommandRuns& runs,
                             const RunInProgress& run, const std::string& trained, const std::set<std::string>& left_out) {
  std::map<std::string, std::string> method_values = run.params.used();
  const MethodEntry& entry = method_entry(run.method_name);
  for (const std::string& key : entry.session_only_parameters) method_values.erase(key);
  for (const std::string& key : left_out) method_values.erase(key);
  if (options.selection != "last" && !entry.base_ignores_selection) method_values["selection"] = options.selection;
  return base_stage_identity({runs.code, trained, plan.dataset.cache_key, runs.run_values, run.seed, plan.threads,
                              plan.evaluation, method_values, &plan.schedules[run.schedule]});
}

// The stage cache's key of the run's base: everything that shapes its base session.
std::string base_identity_of(const RunOptions& options, const CommandPlan& plan, const CommandRuns& runs,
                             const RunInProgress& run) {
  if (!runs.stage_caching()) return {};
  return trained_identity(options, plan, runs, run, run.base_key.empty() ? run.method_name : run.base_key, {});
}

// The key of a stage the run's method shares (MethodEntry::shared_stages), in the command and,
// with the stage cache, across commands.
std::string shared_stage_identity_of(const RunOptions& options, const CommandPlan& plan, const CommandRuns& runs,
                                     const RunInProgress& run, const std::string& stage) {
  const auto& declared = method_entry(run.method_name).shared_stages;
  const auto read_after = declared.find(stage);
  if (read_after == declared.end()) {
    throw MethodError(fmt::format("{} shares a stage \"{}\" that its registry entry does not declare", run.method_name,
                                  stage));
  }
  return trained_identity(options, plan, runs, run, stage, read_after->second);
}

// A fresh method, as every run starts.
void start_fresh(const CommandPlan& plan, RunInProgress& run) {
  run.params = plan.params;
  run.method = create_method(run.method_name, run.params);
}

// The seed's random states (torch's and the context's), as every run starts.
void seed_run(RunInProgress& run) {
  torch::manual_seed(run.seed);
  run.context.generator = std::mt19937_64(run.seed);
}

// The method and both random states as `saved` left them, its sessions counted as done;
// MethodError when the state does not fit the method.
void continue_from(const CommandPlan& plan, RunInProgress& run, RunCheckpoint& saved) {
  describe_protocol(run.context, plan.dataset, plan.schedules[run.schedule]);
  run.method->restore_state(saved.method_state, run.context);
  run.context.generator = saved.generator;
  restore_torch_random_state(saved.torch_random_state);
  run.checkpoints.finished = std::move(saved.outcomes);
  run.seconds_before = saved.elapsed_seconds;
}

// The base from the stage cache, when it holds this base; an entry that does not fit the method
// is removed and the run starts again from scratch.
void take_cached_base(const CommandPlan& plan, const CommandRuns& runs, RunInProgress& run, ProgressReporter& progress) {
  const fs::path cached_file = runs.stage_cache.file_of(run.base_identity);
  std::string dropped;
  // This run trains the base unless it is cached, or another process is training it now: then it waits and takes it.
  std::optional<RunCheckpoint> cached = runs.stage_cache.find_or_claim(
      run.base_identity, dropped, [&](const std::string& line) { progress.note(line); }, run.base_claim);
  if (cached) {
    auto& diagnostics = cached->outcomes.front().diagnostics;
    run.base_peak_bytes = static_cast<std::int64_t>(diagnostics[kCachedPeakKey]);
    diagnostics.erase(kCachedPeakKey);
    try {
      continue_from(plan, run, *cached);
      run.base_from_cache = true;
      run.base_claim.reset();
      progress.note(fmt::format("base session from the stage cache ({}), trained in {:.1f} s by an earlier run",
                                cached_file.string(), run.checkpoints.finished.front().train_seconds));
    } catch (const MethodError& error) {
      dropped = fmt::format("{}: does not fit {}: {}", cached_file.string(), run.method_name, error.what());
      std::error_code ignored;
      fs::remove(cached_file, ignored);
      run.checkpoints.finished.clear();
      run.seconds_before = 0;
      run.base_peak_bytes = 0;
      start_fresh(plan, run);
      seed_run(run);
    }
  }
  if (!dropped.empty()) progress.note(fmt::format("stage cache entry dropped, the base is trained again: {}", dropped));
}

// Step 3: where the run's base session comes from: its own checkpoint (--resume), a method of
// this command that trained the same base, the stage cache, or training (none of these).
void choose_base(const RunOptions& options, const CommandPlan& plan, const CommandRuns& runs, RunInProgress& run,
                 ProgressReporter& progress) {
  if (options.resume && fs::exists(run.checkpoint_file)) {
    RunCheckpoint saved = load_checkpoint(run.checkpoint_file, run.identity);
    try {
      continue_from(plan, run, saved);
    } catch (const MethodError& error) {
      throw ProtocolError(fmt::format("{}: checkpoint does not fit {}: {}", run.checkpoint_file.string(),
                                      run.method_name, error.what()));
    }
    progress.note(fmt::format("continuing after session {} from {}", run.checkpoints.finished.size() - 1,
                              run.checkpoint_file.string()));
    run.stage_progress->clear();  // left when a stop came between the checkpoint and its removal
  } else if (auto found = runs.trained_bases.find({run.base_key, run.seed});
             !run.base_key.empty() && found != runs.trained_bases.end() &&
             run.method->continue_from_base(*found->second.method, run.context)) {
    run.inherited_base = InheritedBase{found->second.seconds, found->second.diagnostics, found->second.training_log};
    run.base_trained_by = found->second.trained_by;
    progress.note(fmt::format("base session shared with {} (same seed, same base training)", run.base_trained_by));
  } else if (runs.stage_caching()) {
    take_cached_base(plan, runs, run, progress);
  }
}

// After every session: the run's checkpoint; after the base session the stages it shares and
// the stage cache's entry.
void checkpoint_after_each_session(const CommandRuns& runs, RunInProgress& run, ProgressReporter& progress) {
  run.checkpoints.after_session = [&runs, &run, &progress](const std::vector<SessionOutcome>& so_far) {
    RunCheckpoint now{run.identity, so_far, run.seconds_before + run.clock.seconds(), run.method->save_state(),
                      run.context.generator, torch_random_state()};
    save_checkpoint(run.checkpoint_file, now);
    if (so_far.size() == 1) run.stage_progress->clear();  // the checkpoint holds the whole base session now
    if (so_far.size() != 1 || !runs.stage_caching() || run.base_from_cache) return;
    std::optional<FileLock> claim;  // let go once the base is filed, or found not to be filed
    claim.swap(run.base_claim);
    if (run_verdict(judge_stages(so_far.front().training_log)) == TrainingVerdict::not_learning) {
      progress.note("base session not cached: its training did not learn");  // a later run would take it as a base
      return;
    }
    try {
      now.outcomes.front().diagnostics[kCachedPeakKey] = static_cast<double>(peak_resident_bytes() - run.resident_at_start);
      runs.stage_cache.store(run.base_identity, now);
    } catch (const std::exception& error) {  // a cache that cannot be written costs time, not the run
      progress.note(fmt::format("stage cache not written: {}", error.what()));
    }
  };
}

// Step 4: the sessions (from where the base left off), and what the run keeps of them on disk.
std::vector<SessionOutcome> run_the_sessions(const RunOptions& options, const CommandPlan& plan, const std::string& commit,
                                             RunInProgress& run) {
  const SessionSchedule& schedule = plan.schedules[run.schedule];
  SavedEmbeddings saved_embeddings;
  ScoredEmbeddingSink keep_embeddings;
  if (plan.save_session) {
    saved_embeddings = embeddings_before_the_stop(plan.save_session, run.checkpoints.finished, run.checkpoint_file);
    keep_embeddings = [&](int session, const torch::Tensor& embeddings, const std::vector<std::int64_t>& labels) {
      if (!plan.save_session(session)) return;
      const torch::Tensor rows = embeddings.to(torch::kFloat).contiguous();
      FloatArray array({rows.size(0), rows.size(1)});
      std::copy(rows.data_ptr<float>(), rows.data_ptr<float>() + rows.numel(), array.values.begin());
      saved_embeddings.embeddings[session] = std::move(array);
      saved_embeddings.labels[session] = std::vector<std::int32_t>(labels.begin(), labels.end());
      saved_embeddings.write(embeddings_so_far_path(run.checkpoint_file), schedule.plan.base_classes);
    };
  }
  const EmbeddingReuse reuse = method_entry(run.method_name).sessions_keep_embedding ? EmbeddingReuse::once_per_run
                                                                                     : EmbeddingReuse::every_session;
  const auto outcomes = run_sessions(*run.method, plan.dataset, schedule, run.context, plan.evaluation,
                                     run.inherited_base, run.checkpoints, keep_embeddings, reuse);
  const fs::path file_name = run_record_file_name(run.record);
  if (plan.save_session) {
    saved_embeddings.write(fs::path(options.out) / "embeddings" / fs::path(file_name).replace_extension(".h5"),
                           schedule.plan.base_classes);
  }
  if (options.save_model) {
    SavedModelMetadata about{run.method_name, options.dataset, run.identity, commit, run.seed,
                             {plan.input.channels, plan.input.mel_bins, plan.input.frames}, {}};
    for (const int dataset_class : schedule.plan.class_order) {
      about.class_order.push_back(plan.dataset.description.class_names.at(static_cast<std::size_t>(dataset_class)));
    }
    save_model(fs::path(options.out) / "models" / fs::path(file_name).replace_extension(".pt"),
               {run.method->save_state(), about});
  }
  return outcomes;
}

// Step 5: the run's record, written as its result file; its base kept for the next method.
void record_run(const RunOptions& options, const CommandPlan& plan, CommandRuns& runs, RunInProgress& run,
                const std::vector<SessionOutcome>& outcomes) {
  const InferenceTiming timing = time_inference(*run.method, plan.dataset, plan.schedules[run.schedule],
                                                kTimedInferenceBatch, require_profile(options.profile).timed_inference_passes);
  const ModelCost cost = run.method->inference_cost(plan.input);
  RunRecord& record = run.record;
  record.machine = runs.machine;
  record.version = harness_version();
  record.git_commit = runs.commit;
  record.dataset_key = plan.dataset.cache_key;
  record.sessions = outcomes;
  record.total_seconds = run.seconds_before + run.clock.seconds();
  record.resident_at_start_bytes = run.resident_at_start;
  record.peak_resident_bytes = std::max<std::int64_t>(peak_resident_bytes(), run.resident_at_start + run.base_peak_bytes);
  record.inference = {cost.macs(), cost.parameters(), cost.trainable_parameters(), timing.seconds_per_sample,
                      timing.batch};
  const ReplayFootprint replay = run.method->replay_footprint();
  record.replay_samples = replay.samples;
  record.replay_bytes = replay.bytes;
  record.method_note = method_entry(run.method_name).table_note;
  if (!run.base_trained_by.empty()) record.parameters["base_training"] = "shared with " + run.base_trained_by;
  if (run.base_from_cache) record.parameters["base_training"] = "from the stage cache";
  if (!record.parameters.count("base_training") && !run.stages->taken().empty()) {
    record.parameters["base_training"] = run.stages->taken();
  }
  save_run_record(options.out, record);
  std::error_code ignored;
  fs::remove(run.checkpoint_file, ignored);  // the result file now holds everything
  fs::remove(embeddings_so_far_path(run.checkpoint_file), ignored);
  run.stage_progress->clear();  // kept by a stage whose base then came from the stage cache
  runs.records.push_back(std::move(record));
  if (!run.base_key.empty()) {
    runs.trained_bases[{run.base_key, run.seed}] = {std::move(run.method),
                                                    run.base_trained_by.empty() ? run.method_name : run.base_trained_by,
                                                    outcomes.front().train_seconds, outcomes.front().diagnostics,
                                                    outcomes.front().training_log};
  }
}

// One (method, seed) run of the command, or its result kept from before an interruption.
void run_one(const RunOptions& options, const CommandPlan& plan, CommandRuns& runs, std::size_t m, std::size_t s,
             ProgressReporter& progress) {
  RunInProgress run;
  run.method_name = plan.method_names[m];
  run.seed = plan.seeds[s];
  run.schedule = s;
  start_fresh(plan, run);
  run.record = planned_run(options, plan, run.method_name, run.params, run.seed);
  run.identity = identity_of(run.record);
  run.checkpoint_file = checkpoint_path(options.out, run.method_name, options.dataset, run.seed);
  const auto done = std::find_if(runs.finished.begin(), runs.finished.end(), [&](const RunRecord& earlier) {
    return earlier.method == run.method_name && earlier.dataset == options.dataset && earlier.seed == run.seed;
  });
  if (done != runs.finished.end()) {
    if (identity_of(*done) != run.identity) {
      throw ProtocolError(fmt::format("{}/results/{}: a result of another run ({}); resume with the command that "
                                      "made it, or use another --out", options.out, run_record_file_name(*done),
                                      differences(*done, run.record)));
    }
    progress.note("finished before the interruption: result kept");
    runs.records.push_back(*done);
    std::error_code ignored;
    fs::remove(run.checkpoint_file, ignored);
    fs::remove(embeddings_so_far_path(run.checkpoint_file), ignored);
    StageProgressFiles::clear(stage_progress_folder(run.checkpoint_file));
    return;
  }
  seed_run(run);
  run.context.recompute_activations = plan.recompute_activations;
  run.context.precision = plan.precision;
  run.context.selection = plan.selection;
  run.context.memory_budget = plan.memory_budget;
  run.context.seed = run.seed;
  run.context.progress = &progress;
  give_back_freed_memory();  // what earlier runs freed would serve this one unseen
  reset_peak_resident();
  run.resident_at_start = resident_bytes();
  run.clock = Stopwatch();
  run.base_key = method_entry(run.method_name).shared_base_key;
  run.base_identity = base_identity_of(options, plan, runs, run);
  run.stages = std::make_unique<RunStages>(
      runs.shared_stages,
      [&](const std::string& stage) { return shared_stage_identity_of(options, plan, runs, run, stage); },
      run.method_name, &progress);
  run.context.stages = run.stages.get();
  // A stage stopped within (a session's end, a time limit) continues from its last kept epoch.
  run.stage_progress = std::make_unique<StageProgressFiles>(
      stage_progress_folder(run.checkpoint_file), run.identity, options.resume, plan.stage_progress_interval,
      [&run] { return run.seconds_before + run.clock.seconds(); },
      [&run](double elapsed) { run.seconds_before = elapsed - run.clock.seconds(); });
  if (!options.resume) run.stage_progress->clear();  // an earlier command's, never continued without --resume
  run.context.stage_progress = run.stage_progress.get();
  choose_base(options, plan, runs, run, progress);
  checkpoint_after_each_session(runs, run, progress);
  const auto outcomes = run_the_sessions(options, plan, runs.commit, run);
  record_run(options, plan, runs, run, outcomes);
}

}  // namespace

int configure_threads(int requested) {
  const int threads = thread_count(requested);
  torch::set_num_threads(threads);
  return threads;
}

// Before any work: --out holds nothing of the user's, and is no sweep's folder (its cells live in
// cells/ and its tables span them: a plain run there would replace them).
void refuse_out_folder_of_others(const RunOptions& options) {
  refuse_files_not_ours(options.out);
  if (options.grid.empty() && fs::is_directory(fs::path(options.out) / "cells")) {
    throw ProtocolError(fmt::format("--out {}: a sweep's folder (it has cells/); a run there would replace the sweep's "
                                    "tables: write to another --out", options.out));
  }
}

bool uses_stage_cache(const RunOptions& options) { return !options.no_cache && !options.no_stage_cache; }

namespace {

CommandSizes sizes_of(const RunOptions& options, const CommandPlan& plan) {
  // Read from a copy: what plan.params records as read goes into every run's identity and result
  // file, and sizing the command for its estimate reads no run's value.
  const ParameterSet params = plan.params;
  CommandSizes sizes{plan.input.channels, plan.input.mel_bins, plan.input.frames, plan.threads, plan.precision,
                     SupervisedSchedule::from(params).batch_size, {},
                     options.no_cache ? std::string() : cache_folder(options).string(), {},
                     describe_removal(plan.schedules.front().plan)};
  const int timed_inference_passes = 1 + require_profile(options.profile).timed_inference_passes;  // and the warm-up
  for (std::size_t i = 0; i < plan.seeds.size(); ++i) {
    const SessionSchedule& schedule = plan.schedules[i];
    RunSizes run;
    run.base_train = static_cast<std::int64_t>(schedule.train.front().size());
    run.base_validation = static_cast<std::int64_t>(schedule.validation.size());
    run.base_classes = schedule.plan.base_classes;
    run.way = schedule.plan.way;
    run.shot = schedule.plan.shot;
    run.sessions = schedule.plan.sessions;
    run.sample_values = plan.input.channels * plan.input.mel_bins * plan.input.frames;
    run.timed_inference_passes = timed_inference_passes;
    const std::vector<std::int64_t>& scored = schedule.scored_segments(plan.evaluation);
    std::vector<int> removed;  // the classes removed by the session before this one
    for (int session = 0; session < run.sessions; ++session) {
      if (session > 0 && !schedule.plan.adds_classes(session)) ++run.removing_sessions;
      const std::int64_t base_removed =
          std::count_if(removed.begin(), removed.end(), [&](int c) { return c < run.base_classes; });
      const std::int64_t novel_removed = static_cast<std::int64_t>(removed.size()) - base_removed;
      run.base_present_before.push_back(session > 0 ? run.base_classes - base_removed : 0);
      run.novel_present_before.push_back(
          session > 0 ? schedule.plan.seen_after(session - 1) - run.base_classes - novel_removed : 0);
      const int seen = schedule.plan.seen_after(session);
      removed = schedule.plan.removed_by(session);
      run.scored.push_back(std::count_if(scored.begin(), scored.end(), [&](std::int64_t segment) {
        const int label = schedule.label[static_cast<std::size_t>(segment)];
        return label < seen && !std::binary_search(removed.begin(), removed.end(), label);
      }));
    }
    sizes.runs[plan.seeds[i]] = run;
  }
  // Training never takes a batch larger than its samples (shuffled_batches), so neither does the
  // calibration: --set batch_size=2147483647 would have it allocate 64 TB.
  std::int64_t largest_base = 1;
  for (const auto& [seed, run] : sizes.runs) largest_base = std::max(largest_base, run.base_train);
  sizes.pretraining_batch = std::min(sizes.pretraining_batch, largest_base);
  for (std::size_t i = 0; i < plan.method_names.size(); ++i) {
    sizes.method_parameters.emplace(plan.method_names[i], plan.method_params[i]);
  }
  return sizes;
}

// What each run of the command should take, in its order (methods, then seeds), at the rates
// `plan` stored for this machine and shape; empty where none are stored: a command never pays a
// calibration for its progress line.
std::vector<double> expected_run_seconds(const RunOptions& options, const CommandPlan& plan) {
  const CommandSizes sizes = sizes_of(options, plan);
  const std::optional<Calibration> stored = stored_machine_rates(sizes);
  if (!stored) return {};
  std::map<std::uint64_t, std::set<std::string>> trained_stages;     // per seed: shared stages trained
  std::set<std::pair<std::string, std::uint64_t>> trained_bases;     // (shared base key, seed)
  std::vector<double> seconds;
  for (const std::string& name : plan.method_names) {
    const MethodEntry& entry = method_entry(name);
    for (const std::uint64_t seed : plan.seeds) {
      const bool base_trained = !entry.shared_base_key.empty() && trained_bases.count({entry.shared_base_key, seed}) > 0;
      seconds.push_back(run_seconds(entry, sizes.method_parameters.at(name), sizes.runs.at(seed), stored->rates,
                                    base_trained, trained_stages[seed]));
      if (!entry.shared_base_key.empty()) trained_bases.insert({entry.shared_base_key, seed});
    }
  }
  return seconds;
}

// "3 of 13 runs done in 6:02; about 24:10 to go": the runs to go at plan's rates, scaled by how
// the command has kept to them so far.
std::string command_progress(const std::vector<double>& expected, std::size_t done, std::size_t runs, double elapsed) {
  std::string line = fmt::format("{} of {} runs done in {}", done, runs, clock_time(elapsed));
  if (done == runs) return line;
  if (expected.empty()) return line + " (no time to go: `fscil-bench plan` once stores this machine's rates)";
  const double expected_so_far = std::accumulate(expected.begin(), expected.begin() + static_cast<long>(done), 0.0);
  const double pace = expected_so_far > 0 ? elapsed / expected_so_far : 1.0;
  const double to_go = pace * std::accumulate(expected.begin() + static_cast<long>(done), expected.end(), 0.0);
  return line + fmt::format("; about {} to go (plan's rates for the runs left, x{:.2f} as this command has run)",
                            clock_time(to_go), pace);
}

}  // namespace

CommandSizes command_sizes(const RunOptions& options) {
  ProgressReporter quiet = ProgressReporter::quiet();
  return sizes_of(options, plan_command(options, quiet));
}

std::string run_benchmark(const RunOptions& options) {
  refuse_out_folder_of_others(options);
  ProgressReporter progress(options.quiet ? nullptr : &std::cerr);
  const Heartbeat heartbeat(progress, std::chrono::seconds(15));  // a long silent step is not a hang
  const CommandPlan plan = plan_command(options, progress);
  const OutFolderLock lock = claim_out_folder(options, plan);
  CommandRuns runs = start_runs(options, plan);
  const std::size_t run_count = plan.method_names.size() * plan.seeds.size();
  // Only a command of several runs says how many are done and what is left.
  const std::vector<double> expected =
      options.quiet || run_count < 2 ? std::vector<double>() : expected_run_seconds(options, plan);
  const Stopwatch command_clock;
  for (std::size_t m = 0; m < plan.method_names.size(); ++m) {
    for (std::size_t s = 0; s < plan.seeds.size(); ++s) {
      stop_if_requested();
      const std::size_t index = m * plan.seeds.size() + s;
      progress.stage(fmt::format("{} on {}, seed {} ({} of {} runs)", plan.method_names[m], options.dataset,
                                 plan.seeds[s], index + 1, run_count));
      run_one(options, plan, runs, m, s, progress);
      if (run_count > 1) progress.note(command_progress(expected, index + 1, run_count, command_clock.seconds()));
    }
  }
  if (options.cell >= 0) {
    return fmt::format("Cell {}: {} result file(s) in {}/results/; tables over every cell: fscil-bench report\n",
                       options.cell, runs.records.size(), options.out);
  }
  return write_reports(options.out, runs.records) +
         fmt::format("Results: {0}/summary.csv, {0}/sessions.csv, {0}/results.tex, costs in {0}/costs.csv and "
                     "{0}/costs.tex, one JSON per run in {0}/results/\n", options.out);
}

}  // namespace fscil
