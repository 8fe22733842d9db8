#pragma once
#include <functional>
#include <map>
#include <memory>
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
