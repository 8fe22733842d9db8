#include "tools/fscil-bench/cells/out_folder_lock.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "core/error.h"

namespace fscil {

namespace {

// What fscil-bench writes in an --out: a folder holding one of them but no .lock was never an
// --out, so the file is the user's and would be replaced.
constexpr const char* kWrittenNames[] = {"summary.csv", "sessions.csv", "results.tex", "costs.csv", "costs.tex",
                                         "index.html", "paper_comparison.csv", "context_analysis.csv", "results",
                                         "logs", "figures", "checkpoints", "cells", "embeddings", "models"};

enum class Locked { yes, busy };

// flock()s `file` (created if needed); busy when another process holds a conflicting lock.
Locked lock_file(const std::filesystem::path& file, int operation, int& descriptor) {
  descriptor = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (descriptor < 0) {
    throw ProtocolError(fmt::format("{}: cannot create the lock file ({})", file.string(), std::strerror(errno)));
  }
  if (::flock(descriptor, operation | LOCK_NB) == 0) return Locked::yes;
  if (errno == EWOULDBLOCK) return Locked::busy;
  if (errno == ENOLCK || errno == ENOSYS || errno == EOPNOTSUPP) return Locked::yes;  // no locks on this file system
  throw ProtocolError(fmt::format("{}: cannot lock ({})", file.string(), std::strerror(errno)));
}

}  // namespace

void refuse_files_not_ours(const std::filesystem::path& folder) {
  std::error_code error;
  if (!std::filesystem::is_directory(folder, error) || std::filesystem::exists(folder / ".lock", error)) return;
  for (const char* name : kWrittenNames) {
    if (std::filesystem::exists(folder / name, error)) {
      throw ProtocolError(fmt::format("--out {}: {} was not written by fscil-bench (the folder has never been an --out) "
                                      "and would be replaced; move it away or choose another --out",
                                      folder.string(), (folder / name).string()));
    }
  }
}

OutFolderLock::OutFolderLock(const std::filesystem::path& folder, Hold hold) {
  refuse_files_not_ours(folder);
  std::error_code error;
  std::filesystem::create_directories(folder, error);
  if (error) throw ProtocolError(fmt::format("--out {}: cannot create the folder ({})", folder.string(), error.message()));
  descriptors_.push_back(-1);
  if (lock_file(folder / ".lock", hold == Hold::whole ? LOCK_EX : LOCK_SH, descriptors_.back()) == Locked::busy) {
    release();
    throw ProtocolError(fmt::format("--out {}: another fscil-bench command is writing there; wait for it or use "
                                    "another --out", folder.string()));
  }
}

OutFolderLock::OutFolderLock(const std::filesystem::path& folder) : OutFolderLock(folder, Hold::whole) {}

OutFolderLock OutFolderLock::shared(const std::filesystem::path& folder) { return OutFolderLock(folder, Hold::shared); }

OutFolderLock::OutFolderLock(const std::filesystem::path& folder, const std::vector<std::string>& runs)
    : OutFolderLock(folder, Hold::shared) {
  for (const auto& run : runs) {
    descriptors_.push_back(-1);
    try {
      if (lock_file(folder / (".lock-" + run), LOCK_EX, descriptors_.back()) == Locked::busy) {
        throw ProtocolError(fmt::format("--out {}: another fscil-bench command runs {}; wait for it", folder.string(), run));
      }
    } catch (...) {
      release();
      throw;
    }
  }
}

OutFolderLock::OutFolderLock(OutFolderLock&& other) noexcept : descriptors_(std::move(other.descriptors_)) {
  other.descriptors_.clear();
}

void OutFolderLock::release() {
  for (int descriptor : descriptors_) {
    if (descriptor >= 0) ::close(descriptor);
  }
  descriptors_.clear();
}

OutFolderLock::~OutFolderLock() { release(); }

}  // namespace fscil
