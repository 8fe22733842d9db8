#include "core/atomic_file.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/text_file.h"
#include "tests/temporary_directory.h"

namespace fscil {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> names_in(const fs::path& folder) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(folder)) names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

std::string this_host() {
  char name[256] = {};
  ::gethostname(name, sizeof(name) - 1);
  std::string host(name);
  for (char& c : host) {
    if (c == '.' || c == '/') c = '_';
  }
  return host;
}

// The pid of a process that has just exited (and been reaped).
pid_t finished_process() {
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  ::waitpid(child, nullptr, 0);
  return child;
}

TEST(AtomicFile, ReplacesWholeAndLeavesNoTemporary) {
  TemporaryDirectory directory;
  const auto path = directory.path() / "sub" / "table.csv";
  write_file_atomically(path, "first\n");
  write_file_atomically(path, "second\n");
  EXPECT_EQ(read_text_file(path), "second\n");
  EXPECT_EQ(names_in(path.parent_path()), std::vector<std::string>{"table.csv"});
}

TEST(AtomicFile, AFailingWriterLeavesTheOldFileAndNoTemporary) {
  TemporaryDirectory directory;
  const auto path = directory.path() / "model.ckpt";
  write_file_atomically(path, "good\n");
  EXPECT_THROW(replace_file_atomically(path,
                                       [](const fs::path& temporary) {
                                         std::ofstream(temporary) << "half";
                                         throw std::invalid_argument("writer failed");
                                       }),
               std::invalid_argument);
  EXPECT_EQ(read_text_file(path), "good\n");
  EXPECT_EQ(names_in(directory.path()), std::vector<std::string>{"model.ckpt"});
}

TEST(AtomicFile, ADirectoryInThePlaceOfTheFileIsOneLineNamingIt) {
  TemporaryDirectory directory;
  const auto path = directory.path() / "results.tex";
  fs::create_directories(path / "inside");
  try {
    write_file_atomically(path, "table\n");
    FAIL() << "expected an error";
  } catch (const FileError& error) {
    EXPECT_EQ(std::string(error.what()), path.string() + ": is a directory, a file was expected");
  }
  EXPECT_EQ(names_in(directory.path()), std::vector<std::string>{"results.tex"});
  EXPECT_TRUE(fs::is_directory(path / "inside"));
}

TEST(AtomicFile, RemovesTemporariesOfDeadProcessesOfThisHostOnly) {
  TemporaryDirectory directory;
  const std::string dead = "cache.h5.tmp-" + this_host() + "-" + std::to_string(finished_process());
  const std::string alive = "cache.h5.tmp-" + this_host() + "-" + std::to_string(::getppid());
  const std::string other_host = "cache.h5.tmp-elsewhere_node-" + std::to_string(finished_process());
  const std::string look_alike = "notes.tmp-" + this_host() + "-12ab";
  for (const auto& name : {dead, alive, other_host, look_alike}) std::ofstream(directory.path() / name) << "x";
  write_file_atomically(directory.path() / "summary.csv", "a,b\n");
  std::vector<std::string> expected = {alive, other_host, look_alike, "summary.csv"};
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(names_in(directory.path()), expected);
}

TEST(FileBatch, ReplacesEveryFileTogether) {
  TemporaryDirectory directory;
  const auto table = directory.path() / "summary.csv", figure = directory.path() / "figures" / "aa.svg";
  write_file_atomically(table, "old\n");
  FileBatch files;
  files.add(table, "first\n");
  files.add(figure, "<svg/>\n");
  files.add(directory.path() / "." / "summary.csv", "new\n");  // one file however spelled; the later content wins
  ASSERT_NE(files.find(directory.path() / "." / "summary.csv"), nullptr);
  EXPECT_EQ(*files.find(directory.path() / "." / "summary.csv"), "new\n");
  EXPECT_EQ(files.find(directory.path() / "costs.csv"), nullptr);
  files.replace_all();
  EXPECT_EQ(read_text_file(table), "new\n");
  EXPECT_EQ(read_text_file(figure), "<svg/>\n");
  EXPECT_EQ(names_in(directory.path()), (std::vector<std::string>{"figures", "summary.csv"}));
  EXPECT_TRUE(files.files().empty());
}

TEST(TextFile, AFileLargerThanItsBoundIsRefusedNamingBoth) {
  TemporaryDirectory directory;
  const auto file = directory.path() / "run.json";
  write_file_atomically(file, std::string(100, 'x'));
  EXPECT_EQ(read_text_file(file, 100, "a result file").size(), 100u);
  try {
    read_text_file(file, 99, "a result file");
    FAIL() << "expected an error";
  } catch (const FileError& error) {
    EXPECT_EQ(std::string(error.what()), file.string() + ": 100 bytes, expected a result file of at most 99 bytes");
  }
}

// A report whose last figure cannot be written (here a folder in its place; a full disk does the
// same) must not leave new tables beside old figures: nothing is replaced, no temporary is left.
TEST(FileBatch, AFileThatCannotBeWrittenLeavesEveryOldFileAsItWas) {
  TemporaryDirectory directory;
  const auto table = directory.path() / "summary.csv", costs = directory.path() / "costs.csv";
  const auto figure = directory.path() / "figures" / "aa.svg";
  write_file_atomically(table, "old table\n");
  write_file_atomically(costs, "old costs\n");
  fs::create_directories(figure);
  FileBatch files;
  files.add(table, "new table\n");
  files.add(costs, "new costs\n");
  files.add(directory.path() / "logs" / "run.csv", "epoch,loss\n");  // a folder the batch would create
  files.add(figure, "<svg/>\n");
  try {
    files.replace_all();
    FAIL() << "expected an error";
  } catch (const FileError& error) {
    EXPECT_EQ(std::string(error.what()), figure.string() + ": is a directory, a file was expected");
  }
  EXPECT_EQ(read_text_file(table), "old table\n");
  EXPECT_EQ(read_text_file(costs), "old costs\n");
  EXPECT_EQ(names_in(directory.path()), (std::vector<std::string>{"costs.csv", "figures", "summary.csv"}));
  EXPECT_EQ(names_in(directory.path() / "figures"), std::vector<std::string>{"aa.svg"});
}

}  // namespace
}  // namespace fscil
