#pragma once
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace fscil {

class Method;
class ParameterSet;

struct MethodEntry {
  std::string name;
  std::string summary;
  std::function<std::unique_ptr<Method>(const ParameterSet& params)> create;
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

// "all", or a comma-separated list of names; throws MethodError naming an unknown method.
std::vector<std::string> resolve_method_names(const std::string& request);
std::unique_ptr<Method> create_method(const std::string& name, const ParameterSet& params);

}  // namespace fscil
