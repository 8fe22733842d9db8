#pragma once
#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>

namespace fscil {

// The whole file as bytes: the one way the harness reads a text file. Throws FileError naming the
// file when it is not a regular file (a folder, a FIFO, a device) or cannot be opened or read.
// With `at_most`, a file larger than that is refused before it is read, the line saying it expected
// `what` (e.g. "a result file") of at most that size: an input that cannot be what it claims costs
// no memory.
std::string read_text_file(const std::filesystem::path& path,
                           std::uintmax_t at_most = std::numeric_limits<std::uintmax_t>::max(),
                           const std::string& what = "");

// "a folder", "a FIFO", "a character device", ...: what a path is, for messages.
std::string kind_of_node(const std::filesystem::file_status& status);

// What `path` is when it names no regular file, for an error message: "no such file", "a folder,
// not a file", "a FIFO, not a regular file", "a loop of symbolic links", ... ("" for a regular file).
std::string why_not_a_regular_file(const std::filesystem::path& path);

// What `path` is when it names no folder: "no such folder", "a file, not a folder", "a FIFO, not a
// folder", ... ("" for a folder, or a link to one).
std::string why_not_a_folder(const std::filesystem::path& path);

}  // namespace fscil
