#include "tools/fscil-bench/options/dataset_defaults.h"
#include "tools/fscil-bench/commands/run_command.h"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <algorithm>
#include <cstdlib>
#include <iostream>
#include <map>
#include <optional>
#include <set>
#include <thread>

#include "datasets/dataset_catalog.h"
#include "datasets/hdf5_file.h"
#include "datasets/segment_cache.h"
#include "methods/common/torch_random_state.h"
#include "methods/method_registry.h"
#include "metrics/resource_usage.h"
#include "protocols/profiles.h"
#include "core/protocol_error.h"
#include "protocols/protocol_runner.h"
#include "protocols/run_checkpoint.h"
#include "protocols/saved_model.h"
#include "protocols/stage_cache.h"
#include "core/stop_request.h"
#include "protocols/session_schedule.h"
#include "reports/comparable_runs.h"
#include "tools/fscil-bench/options/byte_size.h"
#include "tools/fscil-bench/options/machine_info.h"
#include "tools/fscil-bench/cells/out_folder_lock.h"
#include "tools/fscil-bench/commands/report_writer.h"
#include "tools/fscil-bench/options/seed_list.h"

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
  for (const auto& assignment : options.assignments) params.set_assignment(assignment);
  return params;
}

// A --set key that no dataset, protocol or method reads is a typo: refuse it before training.
void reject_unread_keys(const ParameterSet& params, const std::vector<const ParameterSet*>& readers) {
  ParameterSet combined = params;
  for (const auto* reader : readers) combined.mark_read(reader->read_keys());
  const auto unread = combined.unread_keys();
  if (!unread.empty()) {
    throw ProtocolError(fmt::format("--set {}: no dataset, protocol or method of this run reads it",
                                    fmt::join(unread, ", ")));
  }
}

// Everything that shapes a run's numbers; a checkpoint or result file of another run is refused.
std::string identity_of(const RunRecord& record) {
  std::map<std::string, std::string> parameters = record.parameters;
  parameters.erase("base_training");  // how the base was obtained, not what it is
  return fmt::format("method={} dataset={} data={} seed={} threads={} profile={} scored={} selection={} cell={} "
                     "parameters={}", record.method, record.dataset, record.dataset_key, record.seed, record.threads,
                     record.profile, record.evaluated_on, record.selection, grid_cell_name(record.grid),
                     stable_hash(parameters));
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
// profile, split, threads and protocol; per method, the same parameters). A cell is checked even
// as it continues: its folder holds the other cells' runs.
void require_room_for(const std::vector<RunRecord>& planned, const RunOptions& options) {
  if ((options.resume && options.cell < 0) || !holds_results(options.out)) return;
  const std::vector<RunRecord> existing = load_run_records(options.out);
  for (const auto& run : planned) {
    for (const auto& earlier : existing) {
      if (const std::string why = incomparability(earlier, run); !why.empty()) {
        throw ProtocolError(fmt::format("--out {}: {} holds a run that cannot share a table with this one ({}); "
                                        "write to another --out", options.out, earlier.source, why));
      }
    }
  }
}

// The sessions --save-embeddings names, as a test of a session number (of `sessions`).
std::function<bool(int)> sessions_to_save(const std::string& text, int sessions) {
  if (text.empty()) return {};
  if (text == "all") return [](int) { return true; };
  if (text == "last") return [sessions](int session) { return session == sessions - 1; };
  std::set<int> chosen;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    const std::string field = text.substr(start, comma - start);
    char* end = nullptr;
    const long session = std::strtol(field.c_str(), &end, 10);
    if (field.empty() || *end != '\0' || session < 0 || session >= sessions) {
      throw ProtocolError(fmt::format("--save-embeddings {}: expected last, all or session numbers from 0 to {}, "
                                      "comma-separated", text, sessions - 1));
    }
    chosen.insert(static_cast<int>(session));
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

}  // namespace

int configure_threads(int requested) {
  const int threads = requested > 0 ? requested : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  torch::set_num_threads(threads);
  return threads;
}

std::string run_benchmark(const RunOptions& options) {
  if (options.out.empty()) throw ProtocolError("--out '': expected a folder for the results");
  if (!is_selection_name(options.selection)) {
    throw ProtocolError(fmt::format("--selection {}: expected last, validation or test-oracle", options.selection));
  }
  if (options.resume && !fs::is_directory(options.out)) {
    throw ProtocolError(fmt::format("--resume {}: no such folder, nothing to resume (give the --out of the "
                                    "interrupted command)", options.out));
  }
  const auto method_names = resolve_method_names(options.methods);
  const auto seeds = parse_seed_list(options.seeds);
  const int threads = configure_threads(options.threads);
  const ParameterSet params = base_parameters(options);
  ProgressReporter progress(options.quiet ? nullptr : &std::cerr);

  // Methods read their hyper-parameters on construction, so a bad value fails here, early.
  std::vector<ParameterSet> method_params;
  for (const auto& name : method_names) {
    method_params.push_back(params);
    create_method(name, method_params.back());
  }
  ParameterSet protocol_params = params;
  const SplitMode split_mode = parse_split_mode(protocol_params.text("split_mode", "recording"));
  // Activation recomputation: less memory, more time, the same numbers (ResNet18Options).
  const bool recompute_activations = protocol_params.choice("recompute", "none", {"none", "stages"}) == "stages";
  const EvaluationSplit evaluation = parse_evaluation_split(options.evaluate_on);
  const EpochSelection selection = options.selection == "validation"    ? EpochSelection::validation
                                   : options.selection == "test-oracle" ? EpochSelection::test_oracle
                                                                        : EpochSelection::last;
  const std::int64_t memory_limit = options.max_memory.empty() ? 0 : parse_byte_size(options.max_memory, "--max-memory");
  // One budget for the command: a base handed on between runs keeps its encoder, and with it this.
  const auto memory_budget = memory_limit > 0 ? std::make_shared<MemoryBudget>(memory_limit) : nullptr;
  if (memory_limit > 0) return_large_blocks_to_the_kernel();

  DatasetRequest request;
  request.data_root = options.data_root;
  request.cache_dir = options.no_cache ? fs::path() : cache_folder(options);
  request.threads = threads;
  request.features = parse_feature_storage(options.features);
  ParameterSet dataset_params = params;
  progress.stage(fmt::format("preparing dataset {}", options.dataset));
  Stopwatch dataset_clock;
  const PreparedDataset dataset = prepare_dataset(options.dataset, request, dataset_params, std::cerr);
  const InputShape input = input_shape_of(dataset);
  progress.note(fmt::format("{} segments of shape {}x{}x{} ready in {:.1f}s", dataset.segments.count(), input.channels,
                            input.mel_bins, input.frames, dataset_clock.seconds()));

  std::vector<SessionSchedule> schedules;
  for (std::uint64_t seed : seeds) {
    const SessionPlan plan = make_session_plan(static_cast<int>(dataset.description.class_names.size()),
                                               dataset.description.sessions, protocol_params, seed);
    try {
      schedules.push_back(build_session_schedule(dataset.segments, dataset.description.class_names, plan, split_mode,
                                                 seed));
      schedules.back().scored_segments(evaluation);  // refuses, before any training, a split the data lacks
    } catch (const ProtocolError& error) {
      const std::string where = options.data_root.empty() ? "" : fmt::format(" in {}", options.data_root);
      throw ProtocolError(fmt::format("dataset {}{}, {}-way {}-shot: {}", options.dataset, where, plan.way, plan.shot,
                                      error.what()));
    }
  }
  const auto save_session = sessions_to_save(options.save_embeddings, schedules.front().plan.sessions);
  std::vector<const ParameterSet*> readers = {&protocol_params, &dataset_params};
  for (const auto& method_param : method_params) readers.push_back(&method_param);
  reject_unread_keys(params, readers);

  std::map<std::string, std::string> protocol_parameters = dataset_params.used();
  for (const auto& [key, value] : protocol_params.used()) protocol_parameters[key] = value;
  // Like recompute: the same numbers, another peak. Named only when given, so runs without it
  // keep their identity.
  if (memory_limit > 0) protocol_parameters["max_memory"] = std::to_string(memory_limit);
  // Chosen on test or on validation: never one table with runs of the last epoch (named only when
  // given, like max_memory).
  if (options.selection != "last") protocol_parameters["selection"] = options.selection;
  // What a run of this command is before it trains: its identity, and the start of its record.
  const auto planned_run = [&](const std::string& method, const ParameterSet& method_parameters, std::uint64_t seed) {
    RunRecord run;
    run.method = method;
    run.dataset = options.dataset;
    run.profile = options.profile;
    run.seed = seed;
    run.threads = threads;
    run.evaluated_on = to_string(evaluation);
    run.selection = options.selection;
    run.grid = options.grid;
    run.parameters = method_parameters.used();
    for (const auto& [key, value] : protocol_parameters) run.parameters[key] = value;
    run.protocol_parameters = protocol_parameters;
    run.dataset_key = dataset.cache_key;
    return run;
  };
  std::vector<RunRecord> planned;
  for (std::size_t m = 0; m < method_names.size(); ++m) {
    planned.push_back(planned_run(method_names[m], method_params[m], seeds.front()));
  }
  require_room_for(planned, options);
  std::vector<std::string> cell_runs;  // what a --cell command holds of the folder
  for (const auto& method : method_names) {
    for (std::uint64_t seed : seeds) cell_runs.push_back(checkpoint_path("", method, options.dataset, seed).stem().string());
  }
  const OutFolderLock lock = options.cell < 0 ? OutFolderLock(options.out) : OutFolderLock(options.out, cell_runs);

  const auto machine = describe_machine();
  const std::string commit = source_commit();
  // The executable is read only when the stage cache is in use.
  const std::string code = options.no_cache || options.no_stage_cache ? std::string() : code_digest(machine);
  const bool stage_caching = !code.empty();
  const StageCache stage_cache(cache_folder(options) / "stages");
  // What else shapes a base besides the method's values: the front end and dataset knobs (the
  // dataset key covers segments only) and the run-wide recompute (same numbers, another peak).
  std::map<std::string, std::string> run_values = dataset_params.used();
  run_values["front_end"] = dataset.description.front_end.describe();
  run_values["recompute"] = recompute_activations ? "stages" : "none";
  if (memory_limit > 0) run_values["max_memory"] = std::to_string(memory_limit);
  std::vector<RunRecord> records;
  // Per (shared base key, seed): the last method that trained or inherited that base.
  struct TrainedBase {
    std::unique_ptr<Method> method;
    std::string trained_by;
    double seconds = 0;
    std::map<std::string, double> diagnostics;
    std::vector<EpochLog> training_log;
  };
  std::map<std::pair<std::string, std::uint64_t>, TrainedBase> trained_bases;
  const std::vector<RunRecord> finished = finished_runs(options);
  for (std::size_t m = 0; m < method_names.size(); ++m) {
    for (std::size_t s = 0; s < seeds.size(); ++s) {
      stop_if_requested();
      progress.stage(fmt::format("{} on {}, seed {} ({} of {} runs)", method_names[m], options.dataset, seeds[s],
                                 m * seeds.size() + s + 1, method_names.size() * seeds.size()));
      ParameterSet run_params = params;
      auto method = create_method(method_names[m], run_params);
      RunRecord record = planned_run(method_names[m], run_params, seeds[s]);
      const std::string identity = identity_of(record);
      const fs::path checkpoint_file = checkpoint_path(options.out, method_names[m], options.dataset, seeds[s]);
      const auto done = std::find_if(finished.begin(), finished.end(), [&](const RunRecord& run) {
        return run.method == method_names[m] && run.dataset == options.dataset && run.seed == seeds[s];
      });
      if (done != finished.end()) {
        if (identity_of(*done) != identity) {
          throw ProtocolError(fmt::format("{}/results/{}: a result of another run ({}); resume with the command that "
                                          "made it, or use another --out", options.out, run_record_file_name(*done),
                                          identity_of(*done)));
        }
        progress.note("finished before the interruption: result kept");
        records.push_back(*done);
        std::error_code ignored;
        fs::remove(checkpoint_file, ignored);
        continue;
      }
      torch::manual_seed(seeds[s]);
      RunContext context;
      context.recompute_activations = recompute_activations;
      context.selection = selection;
      context.memory_budget = memory_budget;
      context.seed = seeds[s];
      context.generator = std::mt19937_64(seeds[s]);
      context.progress = &progress;
      reset_peak_resident();
      Stopwatch run_clock;
      const std::string base_key = method->shared_base_key();
      std::optional<InheritedBase> inherited_base;
      std::string base_trained_by;
      SessionCheckpoints checkpoints;
      double seconds_before = 0;
      // Everything that shapes this run's base session, for the stage cache.
      std::map<std::string, std::string> base_method_values = run_params.used();
      for (const std::string& key : method->session_only_parameters()) base_method_values.erase(key);
      if (options.selection != "last" && !method->base_ignores_selection()) {
        base_method_values["selection"] = options.selection;
      }
      const std::string base_identity =
          stage_caching ? base_stage_identity({code, base_key.empty() ? method_names[m] : base_key, dataset.cache_key,
                                               run_values, seeds[s], threads, evaluation, base_method_values,
                                               &schedules[s]})
                        : std::string();
      bool base_from_cache = false;
      std::int64_t base_peak_bytes = 0;  // of the run that trained a cached base
      // The method and both random states as `saved` left them, its sessions counted as done;
      // MethodError when the state does not fit the method.
      const auto continue_from = [&](RunCheckpoint& saved) {
        describe_protocol(context, dataset, schedules[s]);
        method->restore_state(saved.method_state, context);
        context.generator = saved.generator;
        restore_torch_random_state(saved.torch_random_state);
        checkpoints.finished = std::move(saved.outcomes);
        seconds_before = saved.elapsed_seconds;
      };
      if (options.resume && fs::exists(checkpoint_file)) {
        RunCheckpoint saved = load_checkpoint(checkpoint_file, identity);
        try {
          continue_from(saved);
        } catch (const MethodError& error) {
          throw ProtocolError(fmt::format("{}: checkpoint does not fit {}: {}", checkpoint_file.string(),
                                          method_names[m], error.what()));
        }
        progress.note(fmt::format("continuing after session {} from {}", checkpoints.finished.size() - 1,
                                  checkpoint_file.string()));
      } else if (auto found = trained_bases.find({base_key, seeds[s]});
                 !base_key.empty() && found != trained_bases.end() &&
                 method->continue_from_base(*found->second.method, context)) {
        inherited_base = InheritedBase{found->second.seconds, found->second.diagnostics, found->second.training_log};
        base_trained_by = found->second.trained_by;
        progress.note(fmt::format("base session shared with {} (same seed, same base training)", base_trained_by));
      } else if (stage_caching) {
        const fs::path cached_file = stage_cache.file_of(base_identity);
        std::string dropped;
        if (std::optional<RunCheckpoint> cached = stage_cache.find(base_identity, dropped)) {
          auto& diagnostics = cached->outcomes.front().diagnostics;
          base_peak_bytes = static_cast<std::int64_t>(diagnostics[kCachedPeakKey]);
          diagnostics.erase(kCachedPeakKey);
          try {
            continue_from(*cached);
            base_from_cache = true;
            progress.note(fmt::format("base session from the stage cache ({}), trained in {:.1f} s by an earlier run",
                                      cached_file.string(), checkpoints.finished.front().train_seconds));
          } catch (const MethodError& error) {
            dropped = fmt::format("{}: does not fit {}: {}", cached_file.string(), method_names[m], error.what());
            std::error_code ignored;
            fs::remove(cached_file, ignored);
            // Start again from scratch: a fresh method, the seed's random states, no sessions done.
            checkpoints.finished.clear();
            seconds_before = 0;
            base_peak_bytes = 0;
            run_params = params;
            method = create_method(method_names[m], run_params);
            torch::manual_seed(seeds[s]);
            context.generator = std::mt19937_64(seeds[s]);
          }
        }
        if (!dropped.empty()) progress.note(fmt::format("stage cache entry dropped, the base is trained again: {}", dropped));
      }
      checkpoints.after_session = [&](const std::vector<SessionOutcome>& so_far) {
        RunCheckpoint now{identity, so_far, seconds_before + run_clock.seconds(), method->save_state(),
                          context.generator, torch_random_state()};
        save_checkpoint(checkpoint_file, now);
        if (so_far.size() != 1 || !stage_caching || base_from_cache) return;
        try {
          now.outcomes.front().diagnostics[kCachedPeakKey] = static_cast<double>(peak_resident_bytes());
          stage_cache.store(base_identity, now);
        } catch (const std::exception& error) {  // a cache that cannot be written costs time, not the run
          progress.note(fmt::format("stage cache not written: {}", error.what()));
        }
      };
      SavedEmbeddings saved_embeddings;
      ScoredEmbeddingSink keep_embeddings;
      if (save_session) {
        keep_embeddings = [&](int session, const torch::Tensor& embeddings, const std::vector<std::int64_t>& labels) {
          if (!save_session(session)) return;
          const torch::Tensor rows = embeddings.to(torch::kFloat).contiguous();
          FloatArray array({rows.size(0), rows.size(1)});
          std::copy(rows.data_ptr<float>(), rows.data_ptr<float>() + rows.numel(), array.values.begin());
          saved_embeddings.embeddings[session] = std::move(array);
          saved_embeddings.labels[session] = std::vector<std::int32_t>(labels.begin(), labels.end());
        };
      }
      const auto outcomes = run_sessions(*method, dataset, schedules[s], context, evaluation, inherited_base,
                                         checkpoints, keep_embeddings);
      if (save_session) {
        saved_embeddings.write(fs::path(options.out) / "embeddings" /
                                   fs::path(run_record_file_name(record)).replace_extension(".h5"),
                               schedules[s].plan.base_classes);
      }
      if (options.save_model) {
        save_model(fs::path(options.out) / "models" / fs::path(run_record_file_name(record)).replace_extension(".pt"),
                   method->save_state());
      }
      const InferenceTiming timing = time_inference(*method, dataset, schedules[s]);
      const ModelCost cost = method->inference_cost(input);

      record.machine = machine;
      record.version = harness_version();
      record.git_commit = commit;
      record.dataset_key = dataset.cache_key;
      for (const auto& outcome : outcomes) {
        record.sessions.push_back({outcome.session, outcome.seen_classes, outcome.accuracy, outcome.train_seconds,
                                   outcome.test_seconds, outcome.context_ratio_mean, outcome.context_ratio_max,
                                   outcome.diagnostics, outcome.training_log});
      }
      record.total_seconds = seconds_before + run_clock.seconds();
      record.peak_resident_bytes = std::max<std::int64_t>(peak_resident_bytes(), base_peak_bytes);
      record.inference = {cost.macs(), cost.parameters(), cost.trainable_parameters(), timing.seconds_per_sample,
                          timing.batch};
      const ReplayFootprint replay = method->replay_footprint();
      record.replay_samples = replay.samples;
      record.replay_bytes = replay.bytes;
      if (!base_trained_by.empty()) record.parameters["base_training"] = "shared with " + base_trained_by;
      if (base_from_cache) record.parameters["base_training"] = "from the stage cache";
      save_run_record(options.out, record);
      std::error_code ignored;
      fs::remove(checkpoint_file, ignored);  // the result file now holds everything
      records.push_back(std::move(record));
      if (!base_key.empty()) {
        trained_bases[{base_key, seeds[s]}] = {std::move(method), base_trained_by.empty() ? method_names[m] : base_trained_by,
                                               outcomes.front().train_seconds, outcomes.front().diagnostics,
                                               outcomes.front().training_log};
      }
    }
  }
  if (options.cell >= 0) {
    return fmt::format("Cell {}: {} result file(s) in {}/results/; tables over every cell: fscil-bench report\n",
                       options.cell, records.size(), options.out);
  }
  return write_reports(options.out, records) +
         fmt::format("Results: {0}/summary.csv, {0}/sessions.csv, {0}/results.tex, costs in {0}/costs.csv and "
                     "{0}/costs.tex, one JSON per run in {0}/results/\n", options.out);
}

}  // namespace fscil
