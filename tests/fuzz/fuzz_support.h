#pragma once
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

namespace fscil::fuzz {

// This process's own folder for the files a reader is handed: under $FSCIL_FUZZ_SCRATCH (tools/fuzz.sh
// removes it, whatever a crash left), else in /dev/shm, since every input goes through a file.
class ScratchFolder {
 public:
  ScratchFolder() {
    std::filesystem::path base = "/dev/shm";
    if (const char* parent = std::getenv("FSCIL_FUZZ_SCRATCH")) {
      base = parent;
    } else if (!std::filesystem::is_directory(base)) {
      base = std::filesystem::temp_directory_path();
    }
    path_ = base / ("fscil-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(path_);
  }
  ~ScratchFolder() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

inline const std::filesystem::path& scratch_folder() {
  static const ScratchFolder folder;
  return folder.path();
}

inline std::string_view text_of(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

// Writes `bytes` to `name` in the scratch folder, replacing what an earlier input left there.
inline std::filesystem::path scratch_file(const std::string& name, std::string_view bytes) {
  const std::filesystem::path path = scratch_folder() / name;
  std::filesystem::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return path;
}

// The reader's documented error is its answer to bad input; any other exception escapes to
// libFuzzer (uncaught: abort) and is kept as a finding.
template <typename Expected, typename Read>
void expect_only(Read&& read) {
  try {
    read();
  } catch (const Expected&) {
  }
}

// A property every accepted input must have; a violation is a finding like a crash.
inline void require(bool holds) {
  if (!holds) std::abort();
}

}  // namespace fscil::fuzz
