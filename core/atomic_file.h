#pragma once
#include <filesystem>
#include <functional>
#include <string>

#include "core/error.h"

namespace fscil {

// The one way the harness writes a file. `write` fills a temporary file beside `path`; it is then
// flushed to disk, renamed over `path` and the folder synced, so a reader (or a crash) sees the
// old file or the whole new one, never half of it. On every failure, `write`'s own exception
// included (rethrown as it was), the temporary is removed and `path` is unchanged. Temporaries
// left in the folder by processes of this host that no longer run (kill -9) are removed first.
void replace_file_atomically(const std::filesystem::path& path,
                             const std::function<void(const std::filesystem::path& temporary)>& write);

// replace_file_atomically with `content` as the file's bytes.
void write_file_atomically(const std::filesystem::path& path, const std::string& content);

}  // namespace fscil
