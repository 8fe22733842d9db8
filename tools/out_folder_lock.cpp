#include "tools/out_folder_lock.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "protocols/protocol_error.h"

namespace fscil {

namespace {

// Locks `descriptor`; false when another process holds a conflicting lock. A file system without
// flock (some cluster mounts) leaves the folder unguarded rather than unusable.
bool try_lock(int descriptor, int operation) {
  if (::flock(descriptor, operation | LOCK_NB) == 0) return true;
  return errno != EWOULDBLOCK;
}

const char* kBusy = "another fscil-bench command is writing there; wait for it or use another --out";

}  // namespace

OutFolderLock::OutFolderLock(const std::filesystem::path& folder, Hold hold) {
  std::error_code error;
  std::filesystem::create_directories(folder, error);
  if (error) throw ProtocolError(fmt::format("--out {}: cannot create the folder ({})", folder.string(), error.message()));
  descriptor_ = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (descriptor_ < 0) {
    throw ProtocolError(fmt::format("--out {}: cannot open the folder ({})", folder.string(), std::strerror(errno)));
  }
  if (!try_lock(descriptor_, hold == Hold::whole ? LOCK_EX : LOCK_SH)) {
    ::close(descriptor_);
    throw ProtocolError(fmt::format("--out {}: {}", folder.string(), kBusy));
  }
}

OutFolderLock::OutFolderLock(const std::filesystem::path& folder) : OutFolderLock(folder, Hold::whole) {}

OutFolderLock OutFolderLock::shared(const std::filesystem::path& folder) { return OutFolderLock(folder, Hold::shared); }

OutFolderLock::OutFolderLock(const std::filesystem::path& folder, int cell) : OutFolderLock(folder, Hold::shared) {
  const std::filesystem::path file = folder / fmt::format(".cell-{}.lock", cell);
  cell_descriptor_ = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (cell_descriptor_ < 0) {
    const std::string reason = std::strerror(errno);
    ::close(descriptor_);
    throw ProtocolError(fmt::format("{}: cannot create the cell's lock file ({})", file.string(), reason));
  }
  if (!try_lock(cell_descriptor_, LOCK_EX)) {
    ::close(cell_descriptor_);
    ::close(descriptor_);
    throw ProtocolError(fmt::format("--out {} --cell {}: another fscil-bench command runs this cell; wait for it",
                                    folder.string(), cell));
  }
}

OutFolderLock::OutFolderLock(OutFolderLock&& other) noexcept
    : descriptor_(other.descriptor_), cell_descriptor_(other.cell_descriptor_) {
  other.descriptor_ = -1;
  other.cell_descriptor_ = -1;
}

OutFolderLock::~OutFolderLock() {
  if (cell_descriptor_ >= 0) ::close(cell_descriptor_);
  if (descriptor_ >= 0) ::close(descriptor_);
}

}  // namespace fscil
