#pragma once
#include <cstdint>
#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "core/error.h"
#include "datasets/prepared_dataset.h"

namespace fscil {

class ParameterSet;

// A real dataset whose files are not on this machine (no --data-root, or no such folder): what
// plan and the cell checks cannot check here, unlike a bad value.
struct DataNotHere : DatasetError {
  using DatasetError::DatasetError;
};

struct CatalogEntry {
  std::string name;
  std::string summary;
  bool simulated = false;
  // The released method configuration it runs with (configs/NAME.json, where one exists): its own
  // name, or that of the real dataset whose protocol it follows (sf-instruments: ns100).
  std::string method_config;
};

// Where log-Mel features live during a run. In memory they are computed once; on demand each batch
// is computed from the raw signals when a method asks for it, so a dataset whose features would
// not fit (simtex-lmt: 4.9 GB) runs in the memory of its signals. Both give the same features.
enum class FeatureStorage { automatic, in_memory, on_demand };
FeatureStorage parse_feature_storage(const std::string& text);
// `automatic` keeps features in memory up to this size.
constexpr std::int64_t kInMemoryFeatureLimitBytes = std::int64_t{1} << 30;

struct DatasetRequest {
  std::filesystem::path data_root;  // required by real datasets
  std::filesystem::path cache_dir;  // empty: no cache
  int threads = 0;
  FeatureStorage features = FeatureStorage::automatic;
};

// Every dataset the CLI knows, simulated and real, one line each.
std::vector<CatalogEntry> dataset_catalog();

// DatasetError naming every dataset of the catalogue unless `name` is one of them.
void require_dataset_name(const std::string& name);

// Loads (from the cache when it holds this exact parameter set) or builds the dataset.
// Reads its knobs (data_seed, context_strength, mel_scale, mel_norm) from params.
// Throws DatasetError naming the file or what is missing.
PreparedDataset prepare_dataset(const std::string& name, const DatasetRequest& request,
                                const ParameterSet& params, std::ostream& log);

}  // namespace fscil
