// logmel: features of an HDF5 signal, and bad inputs refused without output.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <sys/wait.h>

#include <array>
#include <chrono>
#include <csignal>
#include <thread>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include "datasets/hdf5_file.h"
#include "tests/fixtures/dataset_fixtures.h"
#include "tests/temporary_directory.h"
#include "tests/fscil-bench/cli_support.h"

namespace fscil {
namespace {

TEST(Cli, LogMelConvertsAndRejectsBadFilesWithoutWritingOutput) {
  TemporaryDirectory directory;
  const auto input = directory.path() / "in.h5";
  const auto output = directory.path() / "out.h5";
  FloatArray signal({3, 8000});
  for (std::int64_t i = 0; i < signal.size(); ++i) signal.values[i] = static_cast<float>(std::sin(0.01 * i * (1 + i % 3)));
  Hdf5Contents contents;
  contents.floats["signal"] = &signal;
  write_hdf5_atomically(input, contents);
  const std::string settings = " --sample-rate 10000 --n-fft 128 --hop 16 --n-mels 64";
  const CommandResult ok = run_cli("logmel --input " + input.string() + " --output " + output.string() + settings);
  ASSERT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_NE(ok.output.find("Mel filters are empty"), std::string::npos) << "LMT108 settings leave filters empty";
  EXPECT_EQ(read_hdf5_floats(output, "logmel", 3).shape, (std::vector<std::int64_t>{3, 64, 493}));

  const auto wrong_rank = directory.path() / "rank.h5";
  FloatArray cube({2, 2, 100});
  Hdf5Contents cube_contents;
  cube_contents.floats["signal"] = &cube;
  write_hdf5_atomically(wrong_rank, cube_contents);
  const auto truncated = directory.path() / "truncated.h5";
  std::filesystem::copy_file(input, truncated);
  std::filesystem::resize_file(truncated, std::filesystem::file_size(input) / 3);
  const auto nan_file = directory.path() / "nan.h5";
  signal.values[4321] = std::nanf("");
  write_hdf5_atomically(nan_file, contents);
  const auto absent = directory.path() / "absent.h5";

  const struct {
    std::filesystem::path file;
    const char* fragment;
  } cases[] = {{wrong_rank, "has 3 dimensions, expected 2"},
               {truncated, "truncated"},
               {nan_file, "finite values expected"},
               {absent, "no such file"}};
  for (const auto& bad : cases) {
    const auto target = directory.path() / ("out-" + bad.file.stem().string() + ".h5");
    expect_one_error_line(run_cli("logmel --input " + bad.file.string() + " --output " + target.string() + settings),
                          bad.fragment);
    EXPECT_NE(run_cli("logmel --input " + bad.file.string() + " --output " + target.string() + settings).output.find(
                  bad.file.string()),
              std::string::npos);
    EXPECT_FALSE(std::filesystem::exists(target)) << "no output may be written for " << bad.file;
  }
  // The input named as the output, however spelled, is refused before it is read or replaced.
  const auto before = std::filesystem::file_size(input);
  expect_one_error_line(run_cli("logmel --input " + input.string() + " --output " + directory.path().string() +
                                "/./in.h5" + settings),
                        "is the input file");
  EXPECT_EQ(std::filesystem::file_size(input), before);
  // A write past a file-size limit (as on a full disk): one line and exit 1, where HDF5 once
  // segfaulted at exit, and no output.
  const auto limited = directory.path() / "limited.h5";
  const CommandResult full = run_cli("logmel --input " + input.string() + " --output " + limited.string() + settings,
                                     "ulimit -f 8;");
  expect_one_error_line(full, limited.string() + ": cannot write");
  EXPECT_NE(full.output.find("(File too large)"), std::string::npos) << full.output;
  EXPECT_EQ(full.exit_code, 1) << full.output;
  EXPECT_FALSE(std::filesystem::exists(limited));
  // A sample rate at which every Mel filter is empty once wrote -100 dB everywhere and exited 0.
  const auto silent = directory.path() / "silent.h5";
  expect_one_error_line(run_cli("logmel --input " + input.string() + " --output " + silent.string() +
                                " --sample-rate 1e-300 --n-fft 128 --hop 16 --n-mels 64"),
                        "all 64 Mel filters are empty, so every feature would be -100 dB");
  EXPECT_FALSE(std::filesystem::exists(silent));
  // Round seven: 1e308 Hz was accepted with a warning; dataset.json's bound holds here too.
  const CommandResult past = run_cli("logmel --input " + input.string() + " --output " + silent.string() +
                                     " --sample-rate 1e308 --n-fft 64 --hop 16 --n-mels 8");
  expect_one_error_line(past, "--sample-rate");
  EXPECT_NE(past.output.find("expected a number in (0, 10000000]"), std::string::npos) << past.output;
  EXPECT_EQ(past.exit_code, 2) << past.output;
  EXPECT_FALSE(std::filesystem::exists(silent));
  // A folder or an unreadable file as the input is said to be one, not "truncated or corrupt".
  expect_one_error_line(run_cli("logmel --input " + directory.path().string() + " --output " + silent.string() + settings),
                        directory.path().string() + ": a folder, expected an HDF5 file");
  // A folder in the output's place: one line, and no temporary left beside it.
  const auto folder = directory.path() / "folder.h5";
  std::filesystem::create_directory(folder);
  expect_one_error_line(run_cli("logmel --input " + input.string() + " --output " + folder.string() + settings),
                        folder.string() + ": is a directory, a file was expected");
  EXPECT_TRUE(std::filesystem::is_empty(folder));
  for (const auto& entry : std::filesystem::directory_iterator(directory.path())) {
    EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos) << entry.path();
  }
}

}  // namespace
}  // namespace fscil
