#include "datasets/library_versions.h"

#include <fftw3.h>
#include <fmt/format.h>
#include <hdf5.h>
#include <sndfile.h>

namespace fscil {

std::map<std::string, std::string> data_library_versions() {
  unsigned major = 0, minor = 0, release = 0;
  H5get_libversion(&major, &minor, &release);
  return {{"fftw", fftwf_version}, {"hdf5", fmt::format("{}.{}.{}", major, minor, release)},
          {"libsndfile", sf_version_string()}};
}

}  // namespace fscil
