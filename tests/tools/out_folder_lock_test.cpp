#include "tools/out_folder_lock.h"

#include <gtest/gtest.h>

#include <optional>

#include "protocols/protocol_error.h"
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

}  // namespace
}  // namespace fscil
