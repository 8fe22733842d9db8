#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "core/file_lock.h"

namespace fscil {

// Holds an --out folder for one command: a second command on the same folder is refused (its
// result files and checkpoints would interleave). The locks are FileLocks on `.lock` files in the
// folder (core/file_lock.h: they go with the process, kill -9 included). The
// `.lock` file also marks the folder as fscil-bench's (as result files in results/ do): a folder
// with neither that holds a table fscil-bench would replace (summary.csv, index.html, ...) is the
// user's, and is refused.
// Throws ProtocolError when `folder` holds a table fscil-bench would replace, or any file in a folder
// a run writes (checkpoints/, figures/, logs/, models/, ...), but neither a `.lock` nor result files:
// the file is the user's; and when one of those folder names is a file. Checked before any work,
// and again when locking.
void refuse_files_not_ours(const std::filesystem::path& folder);

// Whether a fscil-bench command has written `folder` (it holds a `.lock`, or result files from
// before locks): what --resume may continue.
bool written_by_fscil_bench(const std::filesystem::path& folder);

// Throws ProtocolError when a command is still writing `folder` (its .lock or a cell's .lock-RUN is
// held): its tables would count the runs finished so far as the whole command. Takes no lock and
// creates no file.
void refuse_folder_being_written(const std::filesystem::path& folder);

// Throws CliError when `output` (what `option` names: a folder of tables, a reference CSV) lies in
// a folder of `results` that holds a run's own files (results/, checkpoints/, cells/): every later
// command reading `results` would find it there and refuse the folder.
void refuse_output_among_run_files(const std::string& option, const std::filesystem::path& output,
                                   const std::filesystem::path& results);

class OutFolderLock {
 public:
  // The whole folder (creates it if needed).
  explicit OutFolderLock(const std::filesystem::path& folder);
  // The runs of one cell (--cell K), named as their result files are without extension: the
  // folder shared with the commands of other cells, these runs alone; a command holding the whole
  // folder excludes them all, and they it.
  OutFolderLock(const std::filesystem::path& folder, const std::vector<std::string>& runs);
  // The folder shared: single cells may run below it (run-cells, a sweep's --cell), a command
  // that wants the whole folder may not.
  static OutFolderLock shared(const std::filesystem::path& folder);

 private:
  enum class Hold { whole, shared };
  OutFolderLock(const std::filesystem::path& folder, Hold hold);
  std::vector<FileLock> locks_;
};

}  // namespace fscil
