#include "core/file_lock.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <utility>

#include "core/error.h"

namespace fscil {

namespace {

int operation_of(FileLock::Kind kind) { return kind == FileLock::Kind::exclusive ? LOCK_EX : LOCK_SH; }

}  // namespace

std::optional<FileLock> FileLock::try_lock(const std::filesystem::path& file, Kind kind) {
  const int descriptor = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (descriptor < 0) {
    throw FileError(fmt::format("{}: cannot create the lock file ({})", file.string(), std::strerror(errno)));
  }
  if (::flock(descriptor, operation_of(kind) | LOCK_NB) == 0) return FileLock(descriptor);
  const int error = errno;
  if (error == ENOLCK || error == ENOSYS || error == EOPNOTSUPP) return FileLock(descriptor);  // no locks here
  ::close(descriptor);
  if (error == EWOULDBLOCK) return std::nullopt;
  throw FileError(fmt::format("{}: cannot lock ({})", file.string(), std::strerror(error)));
}

FileLock::~FileLock() {
  if (descriptor_ >= 0) ::close(descriptor_);
}

FileLock::FileLock(FileLock&& other) noexcept : descriptor_(std::exchange(other.descriptor_, -1)) {}

FileLock& FileLock::operator=(FileLock&& other) noexcept {
  if (this != &other) {
    if (descriptor_ >= 0) ::close(descriptor_);
    descriptor_ = std::exchange(other.descriptor_, -1);
  }
  return *this;
}

bool file_is_locked(const std::filesystem::path& file, FileLock::Kind kind) {
  const int descriptor = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
  if (descriptor < 0) return false;
  const bool busy = ::flock(descriptor, operation_of(kind) | LOCK_NB) != 0 && errno == EWOULDBLOCK;
  ::close(descriptor);
  return busy;
}

}  // namespace fscil
