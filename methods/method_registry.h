#pragma once
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
