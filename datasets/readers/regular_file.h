#pragma once
#include <filesystem>

namespace fscil {

// Whether `path` names a regular file. A name no file system takes (too long, say) names none
// either: the overload without an error code would throw filesystem_error past the reader's own
// DatasetError.
inline bool names_a_regular_file(const std::filesystem::path& path) {
  std::error_code unreadable;
  return std::filesystem::is_regular_file(path, unreadable);
}

}  // namespace fscil
