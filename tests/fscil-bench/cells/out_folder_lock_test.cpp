#include "tools/fscil-bench/cells/out_folder_lock.h"

#include <gtest/gtest.h>

#include <functional>
#include <optional>

#include "core/error.h"
#include "tests/temporary_directory.h"

namespace fscil {
namespace {

TEST(OutFolderLock, ASecondCommandOnTheSameFolderIsRefusedUntilTheFirstEnds) {
  TemporaryDirectory directory;
  const auto out = directory.path() / "new" / "out";
  std::optional<OutFolderLock> first(std::in_place, out);
  EXPECT_TRUE(std::filesystem::is_directory(out));
  try {
    OutFolderLock second(directory.path() / "new" / "." / "out");
    FAIL() << "two commands held one --out";
  } catch (const ProtocolError& error) {
    EXPECT_NE(std::string(error.what()).find("another fscil-bench command is writing there"), std::string::npos)
        << error.what();
  }
  const OutFolderLock elsewhere(directory.path() / "other");  // another folder is free
  first.reset();
  EXPECT_NO_THROW(OutFolderLock again(out));
}

TEST(OutFolderLock, CellsShareTheFolderButNotARunAndExcludeAWholeCommand) {
  TemporaryDirectory directory;
  const auto out = directory.path() / "out";
  std::optional<OutFolderLock> cell0(std::in_place, out, std::vector<std::string>{"a__d__seed1", "b__d__seed1"});
  const OutFolderLock cell1(out, {"a__d__seed2"});  // another cell of the same folder runs beside it
  const auto refused = [](const std::function<void()>& take, const std::string& why) {
    try {
      take();
      ADD_FAILURE() << "not refused: " << why;
    } catch (const ProtocolError& error) {
      EXPECT_NE(std::string(error.what()).find(why), std::string::npos) << error.what();
    }
  };
  // Another command's cell with one of the same runs, however its plan numbers it.
  refused([&] { OutFolderLock again(out, {"b__d__seed1"}); }, "another fscil-bench command runs b__d__seed1");
  refused([&] { OutFolderLock whole(out); }, "another fscil-bench command is writing there");
  { const OutFolderLock parent = OutFolderLock::shared(out); }  // run-cells beside its cells
  cell0.reset();
  EXPECT_NO_THROW(OutFolderLock again(out, {"b__d__seed1"}));
  std::optional<OutFolderLock> whole;
  refused([&] { whole.emplace(out); }, "another fscil-bench command is writing there");  // cell 1 still holds it
}

TEST(OutFolderLock, AWholeCommandExcludesEveryCell) {
  TemporaryDirectory directory;
  const OutFolderLock whole(directory.path());
  EXPECT_THROW(OutFolderLock cell(directory.path(), {"a__d__seed1"}), ProtocolError);
  EXPECT_THROW(OutFolderLock::shared(directory.path()), ProtocolError);
}

}  // namespace
}  // namespace fscil
