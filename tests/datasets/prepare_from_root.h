#pragma once
#include <filesystem>
#include <sstream>
#include <string>

#include "datasets/dataset_catalog.h"
#include "core/parameter_set.h"

namespace fscil {

// Loads a real dataset from a fixture tree on 2 threads, progress discarded.
inline PreparedDataset prepare_from_root(const std::string& name, const std::filesystem::path& root,
                                         const ParameterSet& params = {}, const std::filesystem::path& cache = {}) {
  DatasetRequest request;
  request.data_root = root;
  request.cache_dir = cache;
  request.threads = 2;
  std::stringstream log;
  return prepare_dataset(name, request, params, log);
}

}  // namespace fscil
