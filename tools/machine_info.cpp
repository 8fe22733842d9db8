#include "tools/machine_info.h"

#include <unistd.h>

#include <array>
#include <cstdio>
#include <memory>
#include <thread>

#include "fscil_source_commit.h"

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

std::string source_commit() { return FSCIL_SOURCE_COMMIT; }

}  // namespace fscil
