#pragma once
#include <filesystem>
#include <optional>
#include <string>

#include "datasets/prepared_dataset.h"

namespace fscil {

// 64-bit FNV-1a of a canonical parameter text, as 16 hex digits.
std::string stable_hash(const std::string& text);

// HDF5 files of segments + features, one per parameter set. The key hashes every value that
// shapes the data, so a changed parameter never reuses a stale file.
class FeatureCache {
 public:
  explicit FeatureCache(std::filesystem::path directory) : directory_(std::move(directory)) {}

  static std::string key_for(const DatasetDescription& description);
  std::filesystem::path path_for(const DatasetDescription& description) const;

  // Empty when absent; a present but unreadable file is reported and treated as absent.
  std::optional<PreparedDataset> load(const DatasetDescription& description, std::string* problem = nullptr) const;
  void store(const PreparedDataset& dataset) const;

 private:
  std::filesystem::path directory_;
};

}  // namespace fscil
