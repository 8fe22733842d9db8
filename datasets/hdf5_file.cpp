#include "datasets/hdf5_file.h"

#include <H5Cpp.h>
#include <fcntl.h>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <unistd.h>

#include <cstring>
#include <functional>

#include "core/error.h"
#include "core/atomic_file.h"
#include "core/text_file.h"

namespace fscil {

namespace fs = std::filesystem;

namespace {

H5::H5File open_for_reading(const fs::path& path) {
  H5::Exception::dontPrint();
  if (!fs::exists(path)) throw DatasetError(fmt::format("{}: no such file", path.string()));
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (!fs::is_regular_file(status)) {
    throw DatasetError(fmt::format("{}: {}, expected an HDF5 file", path.string(), kind_of_node(status)));
  }
  if (::access(path.c_str(), R_OK) != 0) {
    throw DatasetError(fmt::format("{}: cannot be read ({})", path.string(), std::strerror(errno)));
  }
  try {
    if (!H5::H5File::isHdf5(path.string())) {
      throw DatasetError(fmt::format("{}: not an HDF5 file (or truncated)", path.string()));
    }
    return H5::H5File(path.string(), H5F_ACC_RDONLY);
  } catch (const H5::Exception&) {
    throw DatasetError(fmt::format("{}: cannot open as HDF5 (truncated or corrupt)", path.string()));
  }
}

H5::DataSet open_dataset(const H5::H5File& file, const fs::path& path, const std::string& name) {
  if (!file.nameExists(name)) {
    throw DatasetError(fmt::format("{}: has no dataset '{}'", path.string(), name));
  }
  if (const H5O_type_t type = file.childObjType(name); type != H5O_TYPE_DATASET) {
    throw DatasetError(fmt::format("{}: '{}' is a {}, expected a dataset", path.string(), name,
                                   type == H5O_TYPE_GROUP ? "group" : "named data type"));
  }
  return file.openDataSet(name);
}

std::vector<hsize_t> dims_of(const H5::DataSet& dataset) {
  const H5::DataSpace space = dataset.getSpace();
  std::vector<hsize_t> dims(space.getSimpleExtentNdims());
  space.getSimpleExtentDims(dims.data());
  return dims;
}

// A dataset's shape is the file's word, not its data's: a few hundred bytes of HDF5 can declare
// 2^40 values, which would end in std::bad_alloc or the kernel's out-of-memory killer. What would
// not fit in this machine's memory is refused before anything is allocated.
void require_fits_in_memory(const fs::path& path, const std::string& name, const std::vector<hsize_t>& dims,
                            double value_bytes) {
  const double memory = static_cast<double>(::sysconf(_SC_PHYS_PAGES)) * static_cast<double>(::sysconf(_SC_PAGESIZE));
  double bytes = value_bytes;
  for (const hsize_t size : dims) bytes *= static_cast<double>(size);
  if (bytes > memory) {
    throw DatasetError(fmt::format("{}: dataset '{}' declares {} values ({:.1f} GB), more than this machine's memory "
                                   "({:.1f} GB)", path.string(), name, fmt::join(dims, " x "), bytes / 1e9, memory / 1e9));
  }
}

template <typename Reader>
auto guarded_read(const fs::path& path, const std::string& name, Reader reader) {
  try {
    return reader();
  } catch (const H5::Exception& error) {
    throw DatasetError(fmt::format("{}: dataset '{}' cannot be read ({}): truncated or corrupt",
                                   path.string(), name, error.getDetailMsg()));
  }
}

H5::DataSet write_array(H5::H5File& file, const std::string& name, const std::vector<hsize_t>& dims,
                        const H5::DataType& type, const void* data) {
  H5::DataSpace space(static_cast<int>(dims.size()), dims.data());
  H5::DataSet dataset = file.createDataSet(name, type, space);
  dataset.write(data, type);
  return dataset;
}

H5::StrType utf8_string_type() {
  H5::StrType type(H5::PredType::C_S1, H5T_VARIABLE);
  type.setCset(H5T_CSET_UTF8);
  return type;
}

std::vector<const char*> pointers_to(const std::vector<std::string>& texts) {
  std::vector<const char*> pointers;
  for (const auto& text : texts) pointers.push_back(text.c_str());
  return pointers;
}

// A list of variable-length strings, read as h5py would write it too.
std::vector<std::string> read_strings(const H5::DataType& stored, const H5::DataSpace& space,
                                      const std::function<void(void*, const H5::DataType&)>& read) {
  if (stored.getClass() != H5T_STRING || !H5::StrType(stored.getId()).isVariableStr()) {
    throw DatasetError("not variable-length strings");
  }
  const H5::StrType type = utf8_string_type();
  std::vector<char*> pointers(static_cast<std::size_t>(space.getSimpleExtentNpoints()), nullptr);
  if (pointers.empty()) return {};
  read(pointers.data(), type);
  std::vector<std::string> texts;
  texts.reserve(pointers.size());
  for (char* pointer : pointers) texts.emplace_back(pointer == nullptr ? "" : pointer);  // before the reclaim
  H5::DataSet::vlenReclaim(pointers.data(), type, space);
  return texts;
}

// Bytes the file will take, at least: its data, and room for HDF5's own records (a few KiB a dataset).
std::uintmax_t bytes_to_reserve(const Hdf5Contents& contents) {
  std::uintmax_t bytes = 1 << 20;
  const auto add_texts = [&](const std::vector<std::string>& texts) {
    for (const auto& text : texts) bytes += text.size() + 64;  // heap object, its id, alignment
  };
  for (const auto& [name, array] : contents.floats) bytes += array->values.size() * sizeof(float) + 8192;
  for (const auto& [name, values] : contents.integers) bytes += values.size() * sizeof(std::int32_t) + 8192;
  for (const auto& [name, texts] : contents.strings) add_texts(texts), bytes += 8192;
  for (const auto& [name, table] : contents.tables) {
    bytes += table.values.size() * sizeof(double) + 8192;
    add_texts(table.columns);
  }
  for (const auto& [name, value] : contents.attributes) bytes += 2 * value.size() + 1024;
  return bytes;
}

// HDF5 1.10 cannot close a file whose writes failed, and its exit handler then crashes on it; so
// the space is claimed first, where a full disk or a file-size limit is one clean error, and HDF5
// writes into space that is there (its truncation frees the claim just before).
void reserve_space(const fs::path& file, std::uintmax_t bytes, const fs::path& named) {
  const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw FileError(fmt::format("{}: cannot create ({})", named.string(), std::strerror(errno)));
  const int failure = ::posix_fallocate(fd, 0, static_cast<off_t>(bytes));
  const bool emptied = ::ftruncate(fd, 0) == 0;
  ::close(fd);
  if (failure != 0) {
    throw FileError(fmt::format("{}: cannot write {:.1f} MiB ({})", named.string(), bytes / 1048576.0,
                                std::strerror(failure)));
  }
  if (!emptied) throw FileError(fmt::format("{}: cannot write ({})", named.string(), std::strerror(errno)));
}

bool a_write_failed = false;

}  // namespace

bool hdf5_cannot_shut_down() { return a_write_failed; }

void write_hdf5_atomically(const fs::path& path, const Hdf5Contents& contents) {
  H5::Exception::dontPrint();
  const std::uintmax_t bytes = bytes_to_reserve(contents);
  replace_file_atomically(path, [&](const fs::path& temporary) {
    reserve_space(temporary, bytes, path);
    try {
      H5::H5File file(temporary.string(), H5F_ACC_TRUNC);
      for (const auto& [name, array] : contents.floats) {
        std::vector<hsize_t> dims(array->shape.begin(), array->shape.end());
        write_array(file, name, dims, H5::PredType::NATIVE_FLOAT, array->values.data());
      }
      for (const auto& [name, values] : contents.integers) {
        write_array(file, name, {values.size()}, H5::PredType::NATIVE_INT32, values.data());
      }
      const H5::StrType text = utf8_string_type();
      for (const auto& [name, texts] : contents.strings) {
        write_array(file, name, {texts.size()}, text, pointers_to(texts).data());
      }
      for (const auto& [name, table] : contents.tables) {
        const hsize_t columns = table.columns.size();
        if (columns == 0 || table.values.size() % columns != 0) {
          throw DatasetError(fmt::format("{}: table '{}' has {} values for {} columns", path.string(), name,
                                         table.values.size(), columns));
        }
        H5::DataSet dataset = write_array(file, name, {table.values.size() / columns, columns},
                                          H5::PredType::NATIVE_DOUBLE, table.values.data());
        const hsize_t count = columns;
        dataset.createAttribute("columns", text, H5::DataSpace(1, &count)).write(text, pointers_to(table.columns).data());
      }
      for (const auto& [name, value] : contents.attributes) {
        file.createAttribute(name, text, H5::DataSpace(H5S_SCALAR)).write(text, value);
      }
      file.close();
    } catch (const H5::Exception& error) {
      a_write_failed = true;
      throw DatasetError(fmt::format("{}: cannot write HDF5 ({})", path.string(), error.getDetailMsg()));
    }
  });
}

FloatArray read_hdf5_floats(const fs::path& path, const std::string& name, int expected_rank) {
  const H5::H5File file = open_for_reading(path);
  return guarded_read(path, name, [&] {
    const H5::DataSet dataset = open_dataset(file, path, name);
    if (dataset.getTypeClass() != H5T_FLOAT) {
      throw DatasetError(fmt::format("{}: dataset '{}' is not floating point", path.string(), name));
    }
    const auto dims = dims_of(dataset);
    if (expected_rank >= 0 && static_cast<int>(dims.size()) != expected_rank) {
      throw DatasetError(fmt::format("{}: dataset '{}' has {} dimensions, expected {}", path.string(),
                                     name, dims.size(), expected_rank));
    }
    require_fits_in_memory(path, name, dims, sizeof(float));
    FloatArray array(std::vector<std::int64_t>(dims.begin(), dims.end()));
    dataset.read(array.values.data(), H5::PredType::NATIVE_FLOAT);
    return array;
  });
}

std::vector<std::int32_t> read_hdf5_integers(const fs::path& path, const std::string& name) {
  const H5::H5File file = open_for_reading(path);
  return guarded_read(path, name, [&] {
    const H5::DataSet dataset = open_dataset(file, path, name);
    const auto dims = dims_of(dataset);
    if (dims.size() != 1 || dataset.getTypeClass() != H5T_INTEGER) {
      throw DatasetError(fmt::format("{}: dataset '{}' is not a 1-D integer vector", path.string(), name));
    }
    require_fits_in_memory(path, name, dims, sizeof(std::int32_t));
    std::vector<std::int32_t> values(dims[0]);
    dataset.read(values.data(), H5::PredType::NATIVE_INT32);
    return values;
  });
}

std::vector<std::string> read_hdf5_strings(const fs::path& path, const std::string& name) {
  const H5::H5File file = open_for_reading(path);
  return guarded_read(path, name, [&] {
    const H5::DataSet dataset = open_dataset(file, path, name);
    if (dims_of(dataset).size() != 1) {
      throw DatasetError(fmt::format("{}: dataset '{}' is not a list of strings", path.string(), name));
    }
    try {
      return read_strings(dataset.getDataType(), dataset.getSpace(),
                          [&](void* buffer, const H5::DataType& type) { dataset.read(buffer, type); });
    } catch (const DatasetError&) {
      throw DatasetError(fmt::format("{}: dataset '{}' is not a list of strings", path.string(), name));
    }
  });
}

Hdf5Table read_hdf5_table(const fs::path& path, const std::string& name) {
  const H5::H5File file = open_for_reading(path);
  return guarded_read(path, name, [&] {
    const H5::DataSet dataset = open_dataset(file, path, name);
    const auto dims = dims_of(dataset);
    if (dims.size() != 2 || dataset.getTypeClass() != H5T_FLOAT || !dataset.attrExists("columns")) {
      throw DatasetError(fmt::format("{}: dataset '{}' is not a table (2-D floats with a 'columns' attribute)",
                                     path.string(), name));
    }
    Hdf5Table table;
    const H5::Attribute columns = dataset.openAttribute("columns");
    try {
      table.columns = read_strings(columns.getDataType(), columns.getSpace(),
                                   [&](void* buffer, const H5::DataType& type) { columns.read(type, buffer); });
    } catch (const DatasetError&) {
      throw DatasetError(fmt::format("{}: the columns of dataset '{}' are not strings", path.string(), name));
    }
    if (table.columns.size() != dims[1]) {
      throw DatasetError(fmt::format("{}: dataset '{}' has {} columns but names {}", path.string(), name, dims[1],
                                     table.columns.size()));
    }
    require_fits_in_memory(path, name, dims, sizeof(double));
    table.values.resize(dims[0] * dims[1]);
    if (!table.values.empty()) dataset.read(table.values.data(), H5::PredType::NATIVE_DOUBLE);
    return table;
  });
}

std::string read_hdf5_attribute(const fs::path& path, const std::string& name) {
  const H5::H5File file = open_for_reading(path);
  return guarded_read(path, name, [&] {
    if (!file.attrExists(name)) throw DatasetError(fmt::format("{}: has no attribute '{}'", path.string(), name));
    const H5::Attribute attribute = file.openAttribute(name);
    if (attribute.getTypeClass() != H5T_STRING) {
      throw DatasetError(fmt::format("{}: attribute '{}' is not text", path.string(), name));
    }
    std::string value;
    attribute.read(attribute.getStrType(), value);
    return value;
  });
}

}  // namespace fscil
