#include "datasets/hdf5_file.h"

#include <H5Cpp.h>
#include <fmt/format.h>

#include "datasets/dataset_error.h"
#include "reports/atomic_file.h"

namespace fscil {

namespace fs = std::filesystem;

namespace {

H5::H5File open_for_reading(const fs::path& path) {
  H5::Exception::dontPrint();
  if (!fs::exists(path)) throw DatasetError(fmt::format("{}: no such file", path.string()));
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
  return file.openDataSet(name);
}

std::vector<hsize_t> dims_of(const H5::DataSet& dataset) {
  const H5::DataSpace space = dataset.getSpace();
  std::vector<hsize_t> dims(space.getSimpleExtentNdims());
  space.getSimpleExtentDims(dims.data());
  return dims;
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

void write_array(H5::H5File& file, const std::string& name, const std::vector<hsize_t>& dims,
                 const H5::PredType& type, const void* data) {
  H5::DataSpace space(static_cast<int>(dims.size()), dims.data());
  H5::DataSet dataset = file.createDataSet(name, type, space);
  dataset.write(data, type);
}

}  // namespace

void write_hdf5_atomically(const fs::path& path, const Hdf5Contents& contents) {
  H5::Exception::dontPrint();
  replace_file_atomically(path, [&](const fs::path& temporary) {
    try {
      H5::H5File file(temporary.string(), H5F_ACC_TRUNC);
      for (const auto& [name, array] : contents.floats) {
        std::vector<hsize_t> dims(array->shape.begin(), array->shape.end());
        write_array(file, name, dims, H5::PredType::NATIVE_FLOAT, array->values.data());
      }
      for (const auto& [name, values] : contents.integers) {
        write_array(file, name, {values.size()}, H5::PredType::NATIVE_INT32, values.data());
      }
      for (const auto& [name, text] : contents.texts) {
        write_array(file, name, {text.size()}, H5::PredType::NATIVE_CHAR, text.data());
      }
      file.close();
    } catch (const H5::Exception& error) {
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
    std::vector<std::int32_t> values(dims[0]);
    dataset.read(values.data(), H5::PredType::NATIVE_INT32);
    return values;
  });
}

std::string read_hdf5_text(const fs::path& path, const std::string& name) {
  const H5::H5File file = open_for_reading(path);
  return guarded_read(path, name, [&] {
    const H5::DataSet dataset = open_dataset(file, path, name);
    const auto dims = dims_of(dataset);
    if (dims.size() != 1) {
      throw DatasetError(fmt::format("{}: dataset '{}' is not a text blob", path.string(), name));
    }
    std::string text(dims[0], '\0');
    dataset.read(text.data(), H5::PredType::NATIVE_CHAR);
    return text;
  });
}

}  // namespace fscil
