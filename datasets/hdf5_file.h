#pragma once
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "datasets/float_array.h"

namespace fscil {

// A float64 table: rows x columns, row-major, its column names in the dataset's "columns"
// attribute (what pandas and h5py users expect of a named table).
struct Hdf5Table {
  std::vector<std::string> columns;
  std::vector<double> values;
};

// What one HDF5 file of ours holds, by dataset path: float32 arrays, int32 vectors, lists of
// variable-length UTF-8 strings, float64 tables, and attributes of the root group (variable-length
// strings), all of which h5py reads as they are. Float arrays are borrowed: they can be large and
// must outlive the write.
struct Hdf5Contents {
  std::map<std::string, const FloatArray*> floats;
  std::map<std::string, std::vector<std::int32_t>> integers;
  std::map<std::string, std::vector<std::string>> strings;
  std::map<std::string, Hdf5Table> tables;
  std::map<std::string, std::string> attributes;
};

// Writes to a temporary name beside `path` and renames, so no half file ever carries the name.
// A full disk or a file-size limit is found before HDF5 writes (FileError).
void write_hdf5_atomically(const std::filesystem::path& path, const Hdf5Contents& contents);

// True once a write failed inside HDF5 (an I/O error the space check could not foresee): HDF5 1.10
// then holds a file it cannot close, and its exit handler would crash on it, so the program ends
// without running exit handlers (tools/fscil-bench/command_line.h).
bool hdf5_cannot_shut_down();

// Each reader throws DatasetError naming the file and dataset when it is missing, truncated,
// not HDF5, of the wrong type or of the wrong rank (expected_rank < 0 accepts any rank).
FloatArray read_hdf5_floats(const std::filesystem::path& path, const std::string& dataset,
                            int expected_rank = -1);
std::vector<std::int32_t> read_hdf5_integers(const std::filesystem::path& path, const std::string& dataset);
std::vector<std::string> read_hdf5_strings(const std::filesystem::path& path, const std::string& dataset);
Hdf5Table read_hdf5_table(const std::filesystem::path& path, const std::string& dataset);
// A root attribute; DatasetError naming the file and attribute when it is missing or not text.
std::string read_hdf5_attribute(const std::filesystem::path& path, const std::string& attribute);

}  // namespace fscil
