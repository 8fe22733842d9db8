#include "tools/machine_info.h"

#include <fmt/format.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <memory>
#include <thread>

#ifndef FSCIL_SOURCE_DIR
#define FSCIL_SOURCE_DIR "."
#endif

namespace fscil {

namespace {
std::string command_output(const std::string& command) {
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command.c_str(), "r"), pclose);
  if (!pipe) return "";
  std::string output;
  std::array<char, 256> buffer{};
  while (fgets(buffer.data(), buffer.size(), pipe.get()) != nullptr) output += buffer.data();
  while (!output.empty() && (output.back() == '\n' || output.back() == '\r')) output.pop_back();
  return output;
}
}  // namespace

std::map<std::string, std::string> describe_machine() {
  std::array<char, 256> host{};
  gethostname(host.data(), host.size() - 1);
  return {{"host", host.data()},
          {"hardware_threads", std::to_string(std::thread::hardware_concurrency())},
          {"compiler", __VERSION__},
          {"cpu", command_output("grep -m1 'model name' /proc/cpuinfo 2>/dev/null | cut -d: -f2- | sed 's/^ *//'")},
          {"blas", command_output("readlink -f /usr/lib/x86_64-linux-gnu/libblas.so.3 2>/dev/null")}};
}

std::string source_commit() {
  const std::string git = fmt::format("git -C '{}' ", FSCIL_SOURCE_DIR);
  const std::string commit = command_output(git + "rev-parse HEAD 2>/dev/null");
  if (commit.empty()) return "unknown";
  const bool dirty = !command_output(git + "status --porcelain --untracked-files=no 2>/dev/null").empty();
  return dirty ? commit + "-dirty" : commit;
}

}  // namespace fscil
