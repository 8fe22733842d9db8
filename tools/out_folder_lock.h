#pragma once
#include <filesystem>

namespace fscil {

// Holds an --out folder for one command: a second command on the same folder is refused (its
// result files and checkpoints would interleave). The locks go with the process, kill -9
// included, so nothing is left behind.
class OutFolderLock {
 public:
  // The whole folder (creates it if needed).
  explicit OutFolderLock(const std::filesystem::path& folder);
  // One cell of a plan (--cell K): the folder shared with the commands of other cells, cell K
  // alone; a command holding the whole folder excludes them all, and they it.
  OutFolderLock(const std::filesystem::path& folder, int cell);
  // The folder shared: single cells may run below it (run-cells, a sweep's --cell), a command
  // that wants the whole folder may not.
  static OutFolderLock shared(const std::filesystem::path& folder);
  ~OutFolderLock();
  OutFolderLock(const OutFolderLock&) = delete;
  OutFolderLock& operator=(const OutFolderLock&) = delete;
  OutFolderLock(OutFolderLock&& other) noexcept;
  OutFolderLock& operator=(OutFolderLock&&) = delete;

 private:
  enum class Hold { whole, shared };
  OutFolderLock(const std::filesystem::path& folder, Hold hold);
  int descriptor_ = -1;
  int cell_descriptor_ = -1;
};

}  // namespace fscil
