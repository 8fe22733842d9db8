#include "tools/dataset_defaults.h"

#include <fmt/format.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "protocols/parameter_set.h"
#include "tools/cli_error.h"
#include "tools/data_folder.h"

namespace fscil {

void apply_dataset_defaults(const std::string& dataset, ParameterSet& params) {
  if (dataset.empty() || dataset.find_first_of("/.") != std::string::npos) return;
  const auto file = data_folder() / "configs" / (dataset + ".json");
  std::ifstream in(file);
  if (!in) return;
  try {
    const auto config = nlohmann::json::parse(in);
    for (const auto& [key, value] : config.at("set").items()) params.set_default(key, value.get<std::string>());
  } catch (const nlohmann::json::exception& error) {
    throw CliError(fmt::format("{}: expected {{\"set\": {{\"key\": \"value\", ...}}}} ({})", file.string(), error.what()));
  }
}

}  // namespace fscil
