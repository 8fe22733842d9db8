#pragma once
#include <filesystem>
#include <string>

namespace fscil {

// The whole file as bytes: the one way the harness reads a text file. Throws FileError naming the
// file when it is a folder or cannot be opened or read.
std::string read_text_file(const std::filesystem::path& path);

}  // namespace fscil
