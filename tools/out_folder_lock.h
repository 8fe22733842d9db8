#pragma once
#include <filesystem>

namespace fscil {

// Holds an --out folder for one command: a second command on the same folder is refused (its
// result files and checkpoints would interleave). The lock is on the folder itself and goes with
// the process, kill -9 included, so nothing is left behind.
class OutFolderLock {
 public:
  explicit OutFolderLock(const std::filesystem::path& folder);  // creates the folder if needed
  ~OutFolderLock();
  OutFolderLock(const OutFolderLock&) = delete;
  OutFolderLock& operator=(const OutFolderLock&) = delete;

 private:
  int descriptor_ = -1;
};

}  // namespace fscil
