#pragma once
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace fscil {

class Method;
class ParameterSet;

// key=value defaults a profile applies before --set.
using ParameterDefaults = std::vector<std::pair<std::string, std::string>>;

// The sizes of one run that its time follows (fscil-bench plan's estimate).
struct RunSizes {
  std::int64_t base_train = 0;       // the base session's training samples
  std::int64_t base_validation = 0;  // its validation samples
  int base_classes = 0, way = 0, shot = 0;
  int sessions = 0;                  // including the base session
  int removing_sessions = 0;         // of them, sessions that only remove classes and train nothing
  std::int64_t sample_values = 0;    // one sample's log-Mel values (channels x Mel bins x frames)
  std::vector<std::int64_t> scored;  // per session: the samples it scores (every class seen by then)
  int timed_inference_passes = 8;    // the runner's inference timing: its warm-up and the profile's timed passes
  // Per session s (index s; 0, the base session, holds 0): the base and the novel classes present as
  // it begins, seen and not removed. The runner fills them; sizes made by hand without them are
  // add-only ones, every session adding `way`.
  std::vector<std::int64_t> base_present_before, novel_present_before;
  // Classes the protocol introduces, removed ones included.
  int total_classes() const { return base_classes + way * (sessions - 1 - removing_sessions); }
  // Classes present before incremental session s (1-based): what a session's replay grows with.
  std::int64_t base_classes_before(int session) const {
    return base_present_before.empty() ? base_classes : base_present_before.at(static_cast<std::size_t>(session));
  }
  std::int64_t novel_classes_before(int session) const {
    return novel_present_before.empty() ? static_cast<std::int64_t>(way) * (session - 1)
                                        : novel_present_before.at(static_cast<std::size_t>(session));
  }
  std::int64_t classes_before(int session) const { return base_classes_before(session) + novel_classes_before(session); }
};

// What one stage of a run computes, in the units fscil-bench plan has measured rates for.
struct StageWork {
  std::string stage;
  double trained = 0;     // samples through the encoder forward and backward (training steps)
  double inferred = 0;    // samples through the encoder forward only
  double head_steps = 0;  // optimiser steps of a small head on fixed embeddings, no encoder
  bool base = true;       // part of the base session, which methods with one shared_base_key train once
};

// A method's stages for one run, from the values it read and the run's sizes.
using RunWork = std::function<std::vector<StageWork>(const ParameterSet& read, const RunSizes& sizes)>;

// A method as the runner and the tools know it. What they need of it is declared here, by the
// method, rather than named there.
struct MethodEntry {
  std::string name;
  std::string summary;
  std::function<std::unique_ptr<Method>(const ParameterSet& params)> create;
  // Lists it belongs to besides "all", e.g. "ablation" (--methods ablation runs them in registry order).
  std::vector<std::string> groups = {};
  // The parameters whose sum is its base session's epochs (a cell's cost class).
  std::vector<std::string> base_epoch_keys = {};
  // Its stages' work (fscil-bench plan's time estimate), besides what the runner does for every
  // method (scoring, the inference timing). Every built-in method declares it; without it, the
  // estimate counts base_epoch_keys passes over the base training samples.
  RunWork work = {};
  // How each profile shortens its schedule (protocols/profiles.h): profile name -> defaults; the
  // paper profile changes nothing.
  std::map<std::string, ParameterDefaults> profile_defaults = {};

  // What the runner may share or skip. tests/methods/sessions_keep_embedding_test.cpp and
  // session_only_parameters_test.cpp hold every built-in method to what its entry declares.
  // learn_session() never changes what embed() returns: the runner embeds each scored sample once
  // per run rather than once per session (protocols/scored_embeddings.h).
  bool sessions_keep_embedding = false;
  // Parameters read only after the base session (a session's fine-tuning, PSPC): a base's identity
  // in the stage cache leaves them out, so a sweep over one reuses the base.
  std::set<std::string> session_only_parameters = {};
  // RunContext::selection never changes what train_base() leaves (its epochs are chosen in sessions
  // only): the stage cache shares one base between selections.
  bool base_ignores_selection = false;
  // Stages of its base session that other methods train alike (the runner keeps each for them:
  // RunContext::stages), each with the parameters read only after it; a stage's identity leaves
  // those and session_only_parameters out, so that pits-sc and cop-fscil/cpi share a pretraining.
  std::map<std::string, std::set<std::string>> shared_stages = {};
  // Methods that differ only after the base session name the same key: the runner trains that base
  // once per seed and hands it on (Method::continue_from_base). Empty: the method shares none.
  std::string shared_base_key = {};

  // What a reader is told of its numbers. Empty for a method run as its release runs it; otherwise
  // one line that the results tables and report --paper print as a footnote of its rows, saying
  // what our numbers are of, e.g. "our reading of LDC: its release cannot run ...".
  std::string table_note = {};
};

// The built-in methods, then those added by register_method(), in that order ("all" runs them so).
const std::vector<MethodEntry>& method_registry();

// Adds a method compiled outside this tree, before the command line runs (its main() calls this,
// then fscil_bench_main(): no static self-registration, which linkers drop). Throws MethodError
// for a name that is taken, reserved (all, ablation) or not made of a-z, 0-9 and -_/+.
void register_method(MethodEntry entry);
// The command line closes the registry as it starts: names it has read stay valid, and a later
// register_method() throws MethodError.
void close_method_registry();

// "all", a group ("ablation"), or a comma-separated list of names; throws MethodError naming an
// unknown method.
std::vector<std::string> resolve_method_names(const std::string& request);
// The registry's entry of a method; throws MethodError for an unknown name.
const MethodEntry& method_entry(const std::string& name);
std::unique_ptr<Method> create_method(const std::string& name, const ParameterSet& params);

}  // namespace fscil
