#pragma once
#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "datasets/prepared_dataset.h"

namespace fscil {

class ParameterSet;

struct CatalogEntry {
  std::string name;
  std::string summary;
  bool simulated = false;
};

struct DatasetRequest {
  std::filesystem::path data_root;  // required by real datasets
  std::filesystem::path cache_dir;  // empty: no cache
  int threads = 0;
};

// Every dataset the CLI knows, simulated and real, one line each.
std::vector<CatalogEntry> dataset_catalog();

// Loads (from the cache when it holds this exact parameter set) or builds the dataset.
// Reads its knobs (data_seed, context_strength, mel_scale, mel_norm) from params.
// Throws DatasetError naming the file or what is missing.
PreparedDataset prepare_dataset(const std::string& name, const DatasetRequest& request,
                                const ParameterSet& params, std::ostream& log);

}  // namespace fscil
