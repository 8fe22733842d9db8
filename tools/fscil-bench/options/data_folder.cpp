#include "tools/fscil-bench/options/data_folder.h"

namespace fscil {
namespace {
std::filesystem::path& package_data_folder() {
  static std::filesystem::path folder;
  return folder;
}

bool holds_data(const std::filesystem::path& folder) {
  return std::filesystem::is_directory(folder / "reports" / "reference") && std::filesystem::is_directory(folder / "configs");
}
}  // namespace

void use_package_data_folder(const std::filesystem::path& folder) { package_data_folder() = folder; }

std::filesystem::path data_folder() {
  if (!package_data_folder().empty()) return package_data_folder();
  std::error_code error;
  const auto executable = std::filesystem::read_symlink("/proc/self/exe", error);
  if (!error) {
    const auto installed = executable.parent_path().parent_path() / "share" / "fscil-bench";
    if (holds_data(installed)) return installed;
  }
  return FSCIL_SOURCE_DIR;
}

std::filesystem::path reference_file(const std::string& name) { return data_folder() / "reports" / "reference" / name; }

}  // namespace fscil
