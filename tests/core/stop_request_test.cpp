#include "core/stop_request.h"

#include <gtest/gtest.h>

#include <csignal>

namespace fscil {
namespace {

TEST(StopRequest, ASignalIsRecordedAndThrownWhereTrainingPolls) {
  clear_stop_request();
  install_stop_handlers();
  EXPECT_NO_THROW(stop_if_requested());
  std::raise(SIGTERM);  // recorded, not fatal
  EXPECT_EQ(stop_signal(), SIGTERM);
  try {
    stop_if_requested();
    FAIL() << "no StopRequested after SIGTERM";
  } catch (const StopRequested& stop) {
    EXPECT_EQ(stop.signal(), SIGTERM);
    EXPECT_STREQ(stop.what(), "stopped by SIGTERM");
  }
  clear_stop_request();
  EXPECT_NO_THROW(stop_if_requested());
  std::signal(SIGTERM, SIG_DFL);
  std::signal(SIGINT, SIG_DFL);
}

TEST(StopRequest, ASecondSigtermIsTheSameRequest) {
  clear_stop_request();
  install_stop_handlers();
  std::raise(SIGTERM);
  std::raise(SIGTERM);  // Slurm signals the task, and its batch script passes the signal on
  EXPECT_EQ(stop_signal(), SIGTERM);
  clear_stop_request();
  std::signal(SIGTERM, SIG_DFL);
  std::signal(SIGINT, SIG_DFL);
}

TEST(StopRequest, ASecondCtrlCEndsTheProcessAtOnce) {
  EXPECT_EXIT(
      {
        clear_stop_request();
        install_stop_handlers();
        std::raise(SIGINT);
        std::raise(SIGINT);
        std::_Exit(0);  // not reached
      },
      ::testing::KilledBySignal(SIGINT), "");
}

}  // namespace
}  // namespace fscil
