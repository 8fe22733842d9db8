#pragma once
#include <filesystem>

namespace fscil {

// Where the files fscil-bench reads besides its inputs live (the paper's tables under
// reports/reference/, the released dataset configs under configs/): the package's folder in a
// program built against the installed package (use_package_data_folder), else
// PREFIX/share/fscil-bench when the binary runs from an install prefix (PREFIX/bin/fscil-bench),
// else the source tree fscil-bench was built from.
std::filesystem::path data_folder();

void use_package_data_folder(const std::filesystem::path& folder);

// A file of data_folder()'s reports/reference/ folder, e.g. "paper_tables.csv".
std::filesystem::path reference_file(const std::string& name);

}  // namespace fscil
