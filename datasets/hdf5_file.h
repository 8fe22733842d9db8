#pragma once
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "datasets/float_array.h"

namespace fscil {

// What one HDF5 file of ours holds: float arrays, int32 vectors and text blobs, by dataset path.
// Float arrays are borrowed: they can be large and must outlive the write.
struct Hdf5Contents {
  std::map<std::string, const FloatArray*> floats;
  std::map<std::string, std::vector<std::int32_t>> integers;
  std::map<std::string, std::string> texts;
};

// Writes to a temporary name beside `path` and renames, so no half file ever carries the name.
void write_hdf5_atomically(const std::filesystem::path& path, const Hdf5Contents& contents);

// Each reader throws DatasetError naming the file and dataset when it is missing, truncated,
// not HDF5, of the wrong type or of the wrong rank (expected_rank < 0 accepts any rank).
FloatArray read_hdf5_floats(const std::filesystem::path& path, const std::string& dataset,
                            int expected_rank = -1);
std::vector<std::int32_t> read_hdf5_integers(const std::filesystem::path& path, const std::string& dataset);
std::string read_hdf5_text(const std::filesystem::path& path, const std::string& dataset);

}  // namespace fscil
