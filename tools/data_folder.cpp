#include "tools/data_folder.h"

namespace fscil {

std::filesystem::path data_folder() {
  std::error_code error;
  const auto executable = std::filesystem::read_symlink("/proc/self/exe", error);
  if (!error) {
    const auto installed = executable.parent_path().parent_path() / "share" / "fscil-bench";
    if (std::filesystem::is_directory(installed / "reports" / "reference") &&
        std::filesystem::is_directory(installed / "configs")) {
      return installed;
    }
  }
  return FSCIL_SOURCE_DIR;
}

std::filesystem::path reference_file(const std::string& name) { return data_folder() / "reports" / "reference" / name; }

}  // namespace fscil
