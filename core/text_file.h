#pragma once
#include <filesystem>
#include <string>

namespace fscil {

// The whole file as bytes. Throws ReportError naming the file when it cannot be read.
std::string read_text_file(const std::filesystem::path& path);

}  // namespace fscil
