#pragma once
#include <filesystem>
#include <optional>

namespace fscil {

// An flock() on a file (created if needed), held until the object goes or the process ends
// (kill -9 included). The file is opened for writing so NFS's emulation takes the lock too; on a
// file system without locks it counts as held: unguarded rather than unusable. On a local file
// system flock()s are per open file, so two FileLocks on one file conflict within one process as
// between two (the tests use that); NFS emulates them with POSIX locks, which are per process.
class FileLock {
 public:
  enum class Kind { exclusive, shared };
  // The lock, or nullopt while another holder's conflicts with it. FileError when the file cannot
  // be created or locked.
  static std::optional<FileLock> try_lock(const std::filesystem::path& file, Kind kind);
  ~FileLock();
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;
  FileLock(FileLock&& other) noexcept;
  FileLock& operator=(FileLock&& other) noexcept;

 private:
  explicit FileLock(int descriptor) : descriptor_(descriptor) {}
  int descriptor_ = -1;
};

// Whether some process holds a lock on `file` that `kind` would conflict with; takes none and
// creates no file (false when there is no file).
bool file_is_locked(const std::filesystem::path& file, FileLock::Kind kind);

}  // namespace fscil
