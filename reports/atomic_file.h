#pragma once
#include <filesystem>
#include <string>

namespace fscil {

// Writes `content` to a temporary file beside `path`, then renames it over `path`: a reader
// sees the old file or the whole new one, never half of it. Throws ReportError.
void write_file_atomically(const std::filesystem::path& path, const std::string& content);

std::string read_text_file(const std::filesystem::path& path);

}  // namespace fscil
