#pragma once
#include <memory>
#include <string>
#include <vector>

namespace fscil {

class Method;
class ParameterSet;

struct MethodEntry {
  const char* name;
  const char* summary;
  std::unique_ptr<Method> (*create)(const ParameterSet& params);
};

// The explicit table of every registered method (no static self-registration: linkers drop it).
const std::vector<MethodEntry>& method_registry();

// "all", or a comma-separated list of names; throws MethodError naming an unknown method.
std::vector<std::string> resolve_method_names(const std::string& request);
std::unique_ptr<Method> create_method(const std::string& name, const ParameterSet& params);

}  // namespace fscil
