#include "tools/machine_info.h"

#include <dlfcn.h>
#include <fmt/format.h>
#include <torch/version.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <memory>
#include <thread>

#include "datasets/library_versions.h"
#include "datasets/stable_hash.h"
#include "fscil_build_info.h"

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

// OpenBLAS names its version and build in openblas_get_config(); the BLAS behind libblas.so.3 is
// chosen by Debian's alternatives at run time, so the symbol is looked up, not linked.
std::string openblas_config() {
  using GetConfig = const char* (*)();
  const auto get_config = reinterpret_cast<GetConfig>(dlsym(RTLD_DEFAULT, "openblas_get_config"));
  return get_config != nullptr ? get_config() : "not loaded (another BLAS)";
}

std::string compiler_version() {
#if defined(__clang__)
  return "Clang " __clang_version__;
#else
  return "GCC " __VERSION__;
#endif
}
}  // namespace

std::map<std::string, std::string> library_versions() {
  auto versions = data_library_versions();
  versions["libtorch"] = TORCH_VERSION;
  versions["openblas"] = openblas_config();
  return versions;
}

std::map<std::string, std::string> describe_machine() {
  std::array<char, 256> host{};
  gethostname(host.data(), host.size() - 1);
  auto machine = library_versions();
  machine.insert(
      {{"host", host.data()},
       {"hardware_threads", std::to_string(std::thread::hardware_concurrency())},
       {"compiler", compiler_version()},
       {"cpu", command_output("grep -m1 'model name' /proc/cpuinfo 2>/dev/null | cut -d: -f2- | sed 's/^ *//'")},
       {"blas", command_output("readlink -f /usr/lib/x86_64-linux-gnu/libblas.so.3 2>/dev/null")}});
  return machine;
}

std::string harness_version() { return FSCIL_VERSION; }

std::string source_commit() { return FSCIL_SOURCE_COMMIT; }

std::string code_digest(const std::map<std::string, std::string>& machine) {
  std::ifstream executable("/proc/self/exe", std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(executable)), std::istreambuf_iterator<char>());
  if (!executable.good() && !executable.eof()) return std::string();
  // Libraries as loaded, the CPU and the BLAS behind libblas.so.3: all change float results.
  std::map<std::string, std::string> runtime = machine;
  runtime.erase("host");
  return stable_hash(bytes) + "+" + stable_hash(runtime);
}

std::string version_text() {
  std::string text = fmt::format("fscil-bench {} (commit {})\n", harness_version(), source_commit());
  for (const auto& [library, version] : library_versions()) text += fmt::format("  {:<11}{}\n", library, version);
  return text + fmt::format("  {:<11}{}", "compiler", compiler_version());
}

}  // namespace fscil
