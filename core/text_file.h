#pragma once
#include <filesystem>
#include <string>

namespace fscil {

// The whole file as bytes: the one way the harness reads a text file. Throws FileError naming the
// file when it is not a regular file (a folder, a FIFO, a device) or cannot be opened or read.
std::string read_text_file(const std::filesystem::path& path);

// "a folder", "a FIFO", "a character device", ...: what a path is, for messages.
std::string kind_of_node(const std::filesystem::file_status& status);

}  // namespace fscil
