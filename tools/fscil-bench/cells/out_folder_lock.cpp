#include "tools/fscil-bench/cells/out_folder_lock.h"

#include <fmt/format.h>

#include <vector>

#include "core/error.h"
#include "core/file_lock.h"

namespace fscil {

namespace {

// The tables fscil-bench writes at the top of an --out, replacing what is there: in a folder it never
// held (no .lock, no result files) a file of one of these names is the user's.
constexpr const char* kTableNames[] = {"summary.csv", "sessions.csv", "results.tex", "costs.csv", "costs.tex",
                                       "index.html", "paper_comparison.csv", "context_analysis.csv"};

// The folders a run writes below an --out: in a folder it never held, a file in one of them is the
// user's (a checkpoint of theirs would be removed, a figure or log replaced). Not cell-logs/: Slurm
// writes a task's log there before the task's fscil-bench starts.
constexpr const char* kFolderNames[] = {"results", "checkpoints", "figures", "logs", "models", "embeddings", "cells"};

}  // namespace

bool written_by_fscil_bench(const std::filesystem::path& folder) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (fs::exists(folder / ".lock", error)) return true;
  // Result files mark a folder fscil-bench wrote before it had a .lock, or that was copied without it.
  for (fs::directory_iterator entry(folder / "results", error), end; !error && entry != end; entry.increment(error)) {
    if (entry->path().extension() == ".json") return true;
  }
  return false;
}

void refuse_files_not_ours(const std::filesystem::path& folder) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (!fs::is_directory(folder, error)) return;
  for (const char* name : kFolderNames) {
    const fs::path sub = folder / name;
    if (fs::exists(fs::symlink_status(sub, error)) && !fs::is_directory(fs::symlink_status(sub, error))) {
      throw ProtocolError(fmt::format("--out {}: {} is not a folder, and fscil-bench writes its {} there; move it away "
                                      "or choose another --out", folder.string(), sub.string(), name));
    }
  }
  if (written_by_fscil_bench(folder)) return;
  std::vector<fs::path> would_replace;
  for (const char* name : kTableNames) {
    if (fs::exists(folder / name, error)) would_replace.push_back(folder / name);
  }
  for (const char* name : kFolderNames) {
    fs::recursive_directory_iterator entry(folder / name, error), end;
    for (; !error && entry != end; entry.increment(error)) {
      if (!entry->is_directory(error)) would_replace.push_back(entry->path());
    }
    error.clear();
  }
  if (!would_replace.empty()) {
    throw ProtocolError(fmt::format("--out {}: {} would be replaced, and nothing says fscil-bench wrote it (the "
                                    "folder has no .lock and no result files); move it away or choose another --out",
                                    folder.string(), would_replace.front().string()));
  }
}

void refuse_folder_being_written(const std::filesystem::path& folder) {
  namespace fs = std::filesystem;
  std::error_code error;
  for (fs::directory_iterator entry(folder, error), end; !error && entry != end; entry.increment(error)) {
    const std::string name = entry->path().filename().string();
    if (name != ".lock" && name.rfind(".lock-", 0) != 0) continue;
    // A shared lock is refused while a whole command holds .lock or a cell holds its .lock-RUN; a
    // command that only shares the folder (run-cells) is found through its cells' locks.
    if (file_is_locked(entry->path(), name == ".lock" ? FileLock::Kind::shared : FileLock::Kind::exclusive)) {
      throw ProtocolError(fmt::format("--results {}: a fscil-bench command is still writing there ({} is held); its "
                                      "tables would count the runs finished so far as all of them: wait for it",
                                      folder.string(), name));
    }
  }
}

void refuse_output_among_run_files(const std::string& option, const std::filesystem::path& output,
                                   const std::filesystem::path& results) {
  namespace fs = std::filesystem;
  std::error_code error;
  // Absolute first: weakly_canonical leaves a relative path relative when its first part is missing.
  const fs::path inside = fs::weakly_canonical(fs::absolute(output), error);
  if (error) return;  // an output that cannot be resolved is refused where it is written
  for (const char* run_folder : {"results", "checkpoints", "cells"}) {
    const fs::path folder = fs::weakly_canonical(fs::absolute(results / run_folder), error);
    if (error) continue;
    const fs::path relative = inside.lexically_relative(folder);
    if (!relative.empty() && *relative.begin() != "..") {
      throw CliError(fmt::format("{} {}: inside {}/, which holds a run's own files; every later command reading "
                                 "{} would take it for one: write it elsewhere", option, output.string(),
                                 (results / run_folder).string(), results.string()));
    }
  }
}

OutFolderLock::OutFolderLock(const std::filesystem::path& folder, Hold hold) {
  refuse_files_not_ours(folder);
  std::error_code error;
  std::filesystem::create_directories(folder, error);
  if (error) throw ProtocolError(fmt::format("--out {}: cannot create the folder ({})", folder.string(), error.message()));
  std::optional<FileLock> lock =
      FileLock::try_lock(folder / ".lock", hold == Hold::whole ? FileLock::Kind::exclusive : FileLock::Kind::shared);
  if (!lock) {
    throw ProtocolError(fmt::format("--out {}: another fscil-bench command is writing there; wait for it or use "
                                    "another --out", folder.string()));
  }
  locks_.push_back(std::move(*lock));
}

OutFolderLock::OutFolderLock(const std::filesystem::path& folder) : OutFolderLock(folder, Hold::whole) {}

OutFolderLock OutFolderLock::shared(const std::filesystem::path& folder) { return OutFolderLock(folder, Hold::shared); }

OutFolderLock::OutFolderLock(const std::filesystem::path& folder, const std::vector<std::string>& runs)
    : OutFolderLock(folder, Hold::shared) {
  for (const auto& run : runs) {
    std::optional<FileLock> lock = FileLock::try_lock(folder / (".lock-" + run), FileLock::Kind::exclusive);
    if (!lock) throw ProtocolError(fmt::format("--out {}: another fscil-bench command runs {}; wait for it", folder.string(), run));
    locks_.push_back(std::move(*lock));
  }
}


}  // namespace fscil
