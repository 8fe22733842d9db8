#include "methods/diverged_training.h"

#include <fmt/format.h>

#include <vector>

namespace fscil {

std::string diverged_training(const std::string& what, const std::map<std::string, double>& values) {
  std::vector<std::string> logged;
  if (const auto loss = values.find("loss"); loss != values.end()) logged.push_back(fmt::format("loss {}", loss->second));
  for (const auto& [name, value] : values) {
    if (name != "seconds" && name != "loss") logged.push_back(fmt::format("{} {}", name, value));
  }
  return fmt::format("{}: training diverged ({}); the run writes no result: lower the learning rate or the temperature "
                     "(--set)", what, fmt::join(logged, ", "));
}

}  // namespace fscil
