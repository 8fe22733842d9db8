#include "core/atomic_file.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <mutex>
#include <set>
#include <string_view>
#include <vector>

#include "core/number_text.h"
#include "core/text_file.h"

namespace fscil {

namespace fs = std::filesystem;

namespace {

std::string host_name() {
  char name[256] = {};
  if (::gethostname(name, sizeof(name) - 1) != 0) return "host";
  std::string host(name);
  for (char& c : host) {
    if (c == '.' || c == '/') c = '_';
  }
  return host;
}

// "<file>.tmp-<host>-<pid>": the host keeps processes of other machines sharing the folder (a
// cluster's file system) out of the clean-up below.
std::string temporary_marker() { return fmt::format(".tmp-{}-", host_name()); }

bool process_is_gone(const std::string& digits) {
  if (digits.empty() || digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) return false;
  const auto pid = static_cast<pid_t>(*parse_number<long>(digits));  // at most 9 digits
  return pid > 0 && ::kill(pid, 0) != 0 && errno == ESRCH;
}

void remove_stale_temporaries(const fs::path& folder) {
  const std::string marker = temporary_marker();
  std::error_code error;
  for (fs::directory_iterator entry(folder, error), end; !error && entry != end; entry.increment(error)) {
    const std::string name = entry->path().filename().string();
    const auto at = name.rfind(marker);
    if (at == std::string::npos || !process_is_gone(name.substr(at + marker.size()))) continue;
    std::error_code ignored;
    fs::remove(entry->path(), ignored);
  }
}

std::mutex inputs_mutex;
std::vector<fs::path>& inputs() {
  static std::vector<fs::path> files;
  return files;
}

void refuse_an_input(const fs::path& path) {
  const std::lock_guard<std::mutex> lock(inputs_mutex);
  for (const fs::path& input : inputs()) {
    std::error_code error;
    if (fs::equivalent(path, input, error)) {
      throw FileError(fmt::format("{}: is {}, which this command reads; write to another file", path.string(),
                                  input == path ? "an input" : "the input " + input.string()));
    }
  }
}

std::string system_message() { return std::strerror(errno); }

void sync_file(const fs::path& path, int flags) {
  const int fd = ::open(path.c_str(), flags | O_CLOEXEC);
  if (fd < 0) throw FileError(fmt::format("{}: cannot open to sync ({})", path.string(), system_message()));
  const bool synced = ::fsync(fd) == 0;
  const std::string reason = synced ? "" : system_message();
  ::close(fd);
  if (!synced) throw FileError(fmt::format("{}: cannot sync to disk ({})", path.string(), reason));
}

void write_all(const fs::path& path, std::string_view content) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw FileError(fmt::format("{}: cannot create ({})", path.string(), system_message()));
  while (!content.empty()) {
    const ssize_t written = ::write(fd, content.data(), content.size());
    if (written < 0 && errno == EINTR) continue;
    if (written <= 0) {
      const std::string reason = written < 0 ? system_message() : "nothing written";
      ::close(fd);
      throw FileError(fmt::format("{}: cannot write ({})", path.string(), reason));
    }
    content.remove_prefix(static_cast<std::size_t>(written));
  }
  if (::close(fd) != 0) throw FileError(fmt::format("{}: cannot write ({})", path.string(), system_message()));
}

}  // namespace

void require_replaceable(const fs::path& path) {
  // Renaming over a device, a FIFO or a link would replace the node itself (/dev/full by a file).
  std::error_code error;
  const fs::file_status node = fs::symlink_status(path, error);
  if (fs::is_directory(node)) throw FileError(fmt::format("{}: is a directory, a file was expected", path.string()));
  if (fs::exists(node) && !fs::is_regular_file(node)) {
    throw FileError(fmt::format("{}: is {}; fscil-bench writes only regular files", path.string(), kind_of_node(node)));
  }
  refuse_an_input(path);
}

namespace {

fs::path folder_of(const fs::path& path) { return path.has_parent_path() ? path.parent_path() : fs::path("."); }

// Creates `path`'s folder, checks `path` may be replaced and, with `clean`, clears the folder of
// stale temporaries; returns the temporary to write.
fs::path prepare_temporary(const fs::path& path, bool clean = true) {
  const fs::path folder = folder_of(path);
  std::error_code error;
  fs::create_directories(folder, error);
  if (error) throw FileError(fmt::format("{}: cannot create its folder ({})", path.string(), error.message()));
  require_replaceable(path);
  if (clean) remove_stale_temporaries(folder);
  return path.string() + temporary_marker() + std::to_string(::getpid());
}

// The folders above `path` that do not exist yet, the outermost first; none past one whose state
// cannot be read (it may exist).
std::vector<fs::path> missing_folders(const fs::path& path) {
  std::vector<fs::path> missing;
  for (fs::path folder = folder_of(path); !folder.empty(); folder = folder.parent_path()) {
    std::error_code error;
    const fs::file_status status = fs::symlink_status(folder, error);
    if (fs::exists(status) || (error && error != std::errc::no_such_file_or_directory)) break;
    missing.insert(missing.begin(), folder);
    if (folder == folder.parent_path()) break;
  }
  return missing;
}

void rename_over(const fs::path& temporary, const fs::path& path) {
  if (::rename(temporary.c_str(), path.c_str()) != 0) {
    throw FileError(fmt::format("{}: cannot replace ({})", path.string(), system_message()));
  }
}

void remove_quietly(const fs::path& path) {
  std::error_code ignored;
  fs::remove(path, ignored);
}

}  // namespace

void replace_file_atomically(const fs::path& path, const std::function<void(const fs::path& temporary)>& write) {
  const fs::path temporary = prepare_temporary(path);
  try {
    write(temporary);
    sync_file(temporary, O_RDONLY);
    rename_over(temporary, path);
  } catch (...) {
    remove_quietly(temporary);
    throw;
  }
  sync_file(folder_of(path), O_RDONLY | O_DIRECTORY);
}

void FileBatch::add(const fs::path& path, std::string content) { files_[path.lexically_normal()] = std::move(content); }

const std::string* FileBatch::find(const fs::path& path) const {
  const auto found = files_.find(path.lexically_normal());
  return found == files_.end() ? nullptr : &found->second;
}

void FileBatch::replace_all() {
  std::vector<std::pair<fs::path, fs::path>> written;  // temporary, path
  std::vector<fs::path> created_folders;                 // parents before their children
  std::set<fs::path> folders;                            // cleaned of stale temporaries, synced at the end
  const auto remove_written = [&](std::size_t from) {
    for (std::size_t i = from; i < written.size(); ++i) remove_quietly(written[i].first);
  };
  try {
    for (const auto& [path, content] : files_) {
      const std::vector<fs::path> missing = missing_folders(path);
      created_folders.insert(created_folders.end(), missing.begin(), missing.end());
      const fs::path temporary = prepare_temporary(path, folders.insert(folder_of(path)).second);
      written.emplace_back(temporary, path);
      write_all(temporary, content);
      sync_file(temporary, O_RDONLY);
    }
  } catch (...) {
    remove_written(0);
    for (auto folder = created_folders.rbegin(); folder != created_folders.rend(); ++folder) remove_quietly(*folder);
    throw;
  }
  for (std::size_t i = 0; i < written.size(); ++i) {
    try {
      rename_over(written[i].first, written[i].second);
    } catch (...) {
      remove_written(i);
      throw;
    }
  }
  for (const fs::path& folder : folders) sync_file(folder, O_RDONLY | O_DIRECTORY);
  files_.clear();
}

void never_replace(const fs::path& input) {
  const std::lock_guard<std::mutex> lock(inputs_mutex);
  inputs().push_back(input);
}

void write_file_atomically(const fs::path& path, const std::string& content) {
  replace_file_atomically(path, [&](const fs::path& temporary) { write_all(temporary, content); });
}

}  // namespace fscil
