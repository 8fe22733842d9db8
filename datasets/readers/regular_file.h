#pragma once
#include <algorithm>
#include <filesystem>
#include <string>
#include <system_error>

#include <fmt/format.h>

#include "core/error.h"
#include "core/text_file.h"

namespace fscil {

// Whether `path` names a regular file. A name no file system takes (too long, say) names none
// either: the overload without an error code would throw filesystem_error past the reader's own
// DatasetError.
inline bool names_a_regular_file(const std::filesystem::path& path) {
  std::error_code unreadable;
  return std::filesystem::is_regular_file(path, unreadable);
}

// `file` when it lies inside the data root `root` (canonical) once its symbolic links are resolved;
// throws DatasetError naming where it leads otherwise: a link may not carry a dataset's reads
// out of its folder (to /etc/passwd, or to another dataset's recordings).
inline std::filesystem::path fenced_by_root(const std::filesystem::path& root, const std::filesystem::path& file) {
  namespace fs = std::filesystem;
  std::error_code error;
  const fs::path resolved = fs::weakly_canonical(file, error);
  if (error) return file;  // what it is not is said by the reader (no such file, a loop of links)
  const auto [stop, at] = std::mismatch(root.begin(), root.end(), resolved.begin(), resolved.end());
  if (stop != root.end()) {
    throw DatasetError(fmt::format("{}: leads to {}, outside the data root {}; a dataset reads only files inside its "
                                   "folder (copy the file in)", file.string(), resolved.string(), root.string()));
  }
  return file;
}

}  // namespace fscil
