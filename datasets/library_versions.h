#pragma once
#include <map>
#include <string>

namespace fscil {

// Versions of the libraries the data layer is linked with (FFTW, HDF5, libsndfile), read from the
// libraries themselves at run time, for result files and `fscil-bench --version`.
std::map<std::string, std::string> data_library_versions();

}  // namespace fscil
