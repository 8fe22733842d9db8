#pragma once
// What the tests of the program share: run it as a user would, and read what it wrote.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace fscil {

// This build's program, source tree, version and commit (build_facts.cpp).
std::string built_program();
std::filesystem::path source_folder();
std::string built_version();
std::string built_commit();

struct CommandResult {
  int exit_code;
  std::string output;  // stdout and stderr together
};

// The program under test: the one built beside the tests, or FSCIL_BENCH_UNDER_TEST (another build,
// e.g. an older commit's, to count which cases it fails).
inline std::string program_under_test() {
  const char* other = std::getenv("FSCIL_BENCH_UNDER_TEST");
  if (other == nullptr || *other == '\0') return built_program();
  static const bool said = std::fprintf(stderr, "testing FSCIL_BENCH_UNDER_TEST=%s\n", other) > 0;
  (void)said;
  return other;
}

// `environment`: assignments the shell puts before the command, for this run only.
inline CommandResult run_cli(const std::string& arguments, const std::string& environment = "") {
  const std::string command = environment + " " + program_under_test() + " " + arguments + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  std::string output;
  std::array<char, 512> buffer{};
  while (fgets(buffer.data(), buffer.size(), pipe) != nullptr) output += buffer.data();
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

// The error contract: exactly one line, starting with the program name, non-zero exit.
inline void expect_one_error_line(const CommandResult& result, const std::string& fragment) {
  EXPECT_NE(result.exit_code, 0) << result.output;
  const auto line_start = result.output.find("fscil-bench: error: ");
  ASSERT_NE(line_start, std::string::npos) << result.output;
  const std::string line = result.output.substr(line_start, result.output.find('\n', line_start) - line_start);
  EXPECT_NE(line.find(fragment), std::string::npos) << line;
  EXPECT_EQ(result.output.find("fscil-bench: error: ", line_start + 1), std::string::npos) << result.output;
}

// The accuracies recorded in one result file, as written.
inline std::string accuracies_in(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string line, accuracies;
  while (std::getline(in, line)) {
    if (line.find("\"accuracy\"") != std::string::npos) accuracies += line;
  }
  return accuracies;
}

// Every score of a result file (accuracies all/base/novel/current/harmonic, context ratios), not
// its timings.
inline std::string scores_in(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string line, scores;
  while (std::getline(in, line)) {
    if (line.find("accuracy\"") != std::string::npos || line.find("\"harmonic_mean\"") != std::string::npos ||
        line.find("\"context_ratio_") != std::string::npos) {
      scores += line;
    }
  }
  return scores;
}

inline std::size_t files_in(const std::filesystem::path& folder) {
  if (!std::filesystem::is_directory(folder)) return 0;
  const std::filesystem::directory_iterator entries(folder);
  return static_cast<std::size_t>(std::distance(begin(entries), end(entries)));
}

// The lines of a text file.
inline std::vector<std::string> lines_of(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

inline std::string read_text(const std::filesystem::path& file) {
  std::ifstream in(file);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace fscil
