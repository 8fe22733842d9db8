#pragma once
#include <filesystem>
#include <optional>
#include <string>

#include "datasets/prepared_dataset.h"
#include "core/stable_hash.h"

namespace fscil {

// HDF5 files of segments (signals and their bookkeeping), one per dataset and segmentation.
// Features are not stored: the front end recomputes them faster than HDF5 reads them back.
// The key hashes every value that shapes the segments, so a changed one never reuses a stale file.
class SegmentCache {
 public:
  explicit SegmentCache(std::filesystem::path directory) : directory_(std::move(directory)) {}

  static std::string key_for(const DatasetDescription& description);
  std::filesystem::path path_for(const DatasetDescription& description) const;

  // Empty when absent; a present but unreadable file is reported and treated as absent.
  std::optional<SegmentSet> load(const DatasetDescription& description, std::string* problem = nullptr) const;
  void store(const DatasetDescription& description, const SegmentSet& segments) const;

 private:
  std::filesystem::path directory_;
};

}  // namespace fscil
