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
// Refuses a `path` that is anything but a regular file or a new name (a folder, link, FIFO, device).
void replace_file_atomically(const std::filesystem::path& path,
                             const std::function<void(const std::filesystem::path& temporary)>& write);

// Marks `input` as a file this process reads its results from (a result file, a reference table):
// replace_file_atomically refuses to write over it for the rest of the process (`reference --out`
// naming the results it reads, `rerun --out` the original folder).
void never_replace(const std::filesystem::path& input);

// Throws FileError unless replace_file_atomically may write `path` (a regular file or a new name,
// not an input): for commands that check their output before their work.
void require_replaceable(const std::filesystem::path& path);

// replace_file_atomically with `content` as the file's bytes.
void write_file_atomically(const std::filesystem::path& path, const std::string& content);

}  // namespace fscil
