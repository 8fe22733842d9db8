#include "tools/fscil-bench/options/machine_info.h"

#include <ATen/Version.h>
#include <dlfcn.h>
#include <fmt/format.h>
#include <torch/version.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <memory>
#include <thread>

#include "datasets/library_versions.h"
#include "core/stable_hash.h"
#include "fscil_build_info.h"
#include "tools/fscil-bench/options/data_folder.h"

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

// What OpenBLAS's `const char* symbol()` returns, or `absent`: the BLAS behind libblas.so.3 is
// chosen by Debian's alternatives at run time, so its functions are looked up, not linked.
std::string text_of(const char* symbol, const char* absent) {
  using GetText = const char* (*)();
  const auto get_text = reinterpret_cast<GetText>(dlsym(RTLD_DEFAULT, symbol));
  const char* text = get_text != nullptr ? get_text() : nullptr;
  return text != nullptr ? text : absent;
}

// LibTorch 1.13 exports no getter for the capability its CPU kernels dispatch to, but names it in
// its configuration text.
std::string aten_capability() {
  const std::string config = at::show_config();
  const std::string label = "CPU capability usage: ";
  const auto start = config.find(label);
  if (start == std::string::npos) return "unknown";
  std::string capability = config.substr(start + label.size(), config.find('\n', start) - start - label.size());
  std::replace(capability.begin(), capability.end(), ' ', '_');  // "NO AVX" as one word
  return capability;
}

// oneDNN comes with LibTorch, which does not install its headers: looked up, not linked.
std::string onednn_isa() {
  using GetIsa = int (*)();
  const auto get_isa = reinterpret_cast<GetIsa>(dlsym(RTLD_DEFAULT, "dnnl_get_effective_cpu_isa"));
  if (get_isa == nullptr) return "none";
  const int isa = get_isa();
  // dnnl_cpu_isa_t of oneDNN 2.x (oneapi/dnnl/dnnl_types.h).
  switch (isa) {
    case 0x1: return "sse41";
    case 0x3: return "avx";
    case 0x7: return "avx2";
    case 0x407: return "avx2_vnni";
    case 0x27: return "avx512_core";
    case 0x67: return "avx512_core_vnni";
    case 0xe7: return "avx512_core_bf16";
    case 0x3e7: return "avx512_core_amx";
    default: return fmt::format("isa_{:#x}", isa);
  }
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
  // OpenBLAS names its version and build; another BLAS has no such function.
  versions["openblas"] = text_of("openblas_get_config", "not loaded (another BLAS)");
  return versions;
}

// The environment variables ATEN_CPU_CAPABILITY, OPENBLAS_CORETYPE and ONEDNN_MAX_CPU_ISA lower
// what each library picks; the reference protocol sets them (README, "Reference numbers").
std::string numeric_kernels() {
  return fmt::format("aten={} openblas={} onednn={}", aten_capability(), text_of("openblas_get_corename", "none"),
                     onednn_isa());
}

bool bf16_is_native() {
  const std::string isa = onednn_isa();
  return isa == "avx512_core_bf16" || isa == "avx512_core_amx";
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
       {"blas", command_output("readlink -f /usr/lib/x86_64-linux-gnu/libblas.so.3 2>/dev/null")},
       {"kernels", numeric_kernels()}});
  return machine;
}

std::string harness_version() { return FSCIL_VERSION; }

std::string source_commit() { return FSCIL_SOURCE_COMMIT; }

std::string code_digest(const std::map<std::string, std::string>& machine) {
  std::ifstream executable("/proc/self/exe", std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(executable)), std::istreambuf_iterator<char>());
  if (!executable.good() && !executable.eof()) return std::string();
  // Libraries as loaded, the CPU, the BLAS behind libblas.so.3 and the kernels: all change float results.
  std::map<std::string, std::string> runtime = machine;
  runtime.erase("host");
  return stable_hash(bytes) + "+" + stable_hash(runtime);
}

std::string version_text() {
  std::string text = fmt::format("fscil-bench {} (commit {})\n", harness_version(), source_commit());
  for (const auto& [library, version] : library_versions()) text += fmt::format("  {:<11}{}\n", library, version);
  text += fmt::format("  {:<11}{}\n", "kernels", numeric_kernels());
  text += fmt::format("  {:<11}{}\n", "compiler", compiler_version());
  return text + fmt::format("  {:<11}{}", "data", data_folder().string());
}

}  // namespace fscil
