#include "tools/fscil-bench/options/dataset_defaults.h"

#include <fmt/format.h>

#include <filesystem>

#include "core/parameter_set.h"
#include "core/error.h"
#include "datasets/dataset_catalog.h"
#include "tools/fscil-bench/options/config_file.h"
#include "tools/fscil-bench/options/data_folder.h"

namespace fscil {

void apply_dataset_defaults(const std::string& dataset, ParameterSet& params) {
  const auto folder = data_folder() / "configs";
  // A binary that lost its data folder would run LS-100 and NS-100 with other values, silently.
  if (!std::filesystem::is_directory(folder)) {
    throw Error(fmt::format("{}: no such folder (the released dataset configs); run fscil-bench from its build "
                               "tree or its install prefix", folder.string()));
  }
  if (dataset.empty() || dataset.find_first_of("/.") != std::string::npos) return;
  std::string config = dataset;
  for (const auto& entry : dataset_catalog()) {
    if (entry.name == dataset) config = entry.method_config;
  }
  const auto file = folder / (config + ".json");
  if (!std::filesystem::exists(file)) return;
  for (const auto& [key, value] : ConfigFile(file).settings()) params.set_default(key, value);
}

}  // namespace fscil
