#pragma once
#include <filesystem>
#include <functional>
#include <map>
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

// Files that replace their old versions together (a report's tables, figures and page): every
// file's temporary is written and synced before any is renamed, so a failure while writing (a
// full disk, a folder that refuses new files) removes the temporaries, and the folders the batch
// created, and leaves every old file as it was, never a folder of some new tables beside old ones.
// Only a rename failing part-way (within one folder, after every write succeeded) could leave some
// files replaced. Paths are kept as lexically_normal(): "out/./a" and "out/a" are one file.
class FileBatch {
 public:
  // Adds `path` with `content`, or replaces the content added for it before.
  void add(const std::filesystem::path& path, std::string content);
  // The content added for `path`, or nullptr.
  const std::string* find(const std::filesystem::path& path) const;
  // By normal path.
  const std::map<std::filesystem::path, std::string>& files() const { return files_; }
  // Writes them all as above; the batch is empty afterwards.
  void replace_all();

 private:
  std::map<std::filesystem::path, std::string> files_;
};

}  // namespace fscil
