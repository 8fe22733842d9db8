#include "core/text_file.h"

#include <fmt/format.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>
#include <system_error>

#include "core/error.h"

namespace fscil {

std::string kind_of_node(const std::filesystem::file_status& status) {
  switch (status.type()) {
    case std::filesystem::file_type::directory: return "a folder";
    case std::filesystem::file_type::symlink: return "a symbolic link";
    case std::filesystem::file_type::block: return "a block device";
    case std::filesystem::file_type::character: return "a character device";
    case std::filesystem::file_type::fifo: return "a FIFO";
    case std::filesystem::file_type::socket: return "a socket";
    case std::filesystem::file_type::regular: return "a file";
    default: return "something other than a file";
  }
}

namespace {

// What `path` is when it is no node of type `wanted` (a regular file or a folder); "" when it is.
std::string why_not(const std::filesystem::path& path, std::filesystem::file_type wanted) {
  namespace fs = std::filesystem;
  const bool folder = wanted == fs::file_type::directory;
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (error == std::errc::too_many_symbolic_link_levels) return "a loop of symbolic links";
  switch (status.type()) {
    case fs::file_type::not_found:
      if (fs::is_symlink(fs::symlink_status(path, error))) return "a symbolic link to nothing";
      return folder ? "no such folder" : "no such file";
    case fs::file_type::none:
    case fs::file_type::unknown:
      if (error) return "unreadable (" + error.message() + ")";
      return folder ? "not a folder" : "not a regular file";
    default:
      if (status.type() == wanted) return "";
      if (folder) return kind_of_node(status) + ", not a folder";
      return kind_of_node(status) + (fs::is_directory(status) ? ", not a file" : ", not a regular file");
  }
}

}  // namespace

std::string why_not_a_regular_file(const std::filesystem::path& path) {
  return why_not(path, std::filesystem::file_type::regular);
}

std::string why_not_a_folder(const std::filesystem::path& path) {
  return why_not(path, std::filesystem::file_type::directory);
}

std::string read_text_file(const std::filesystem::path& path, std::uintmax_t at_most, const std::string& what) {
  std::error_code error;
  const auto status = std::filesystem::status(path, error);
  if (std::filesystem::is_directory(status)) {
    throw FileError(fmt::format("{}: expected a file, found a folder", path.string()));
  }
  // A FIFO with no writer would block for ever, a device could be endless: only files are read.
  if (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status)) {
    throw FileError(fmt::format("{}: expected a regular file, found {}", path.string(), kind_of_node(status)));
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError(fmt::format("{}: cannot open ({})", path.string(), std::strerror(errno)));
  const auto too_large = [&](std::uintmax_t size) {
    return FileError(fmt::format("{}: {} bytes, expected {} of at most {} bytes", path.string(), size,
                                 what.empty() ? std::string("a file") : what, at_most));
  };
  if (const std::uintmax_t size = std::filesystem::file_size(path, error); !error && size > at_most) throw too_large(size);
  // Read in chunks and counted, so a file that grows after its size was taken is bounded too.
  std::string text;
  std::vector<char> chunk(1 << 16);
  while (in.read(chunk.data(), static_cast<std::streamsize>(chunk.size())) || in.gcount() > 0) {
    text.append(chunk.data(), static_cast<std::size_t>(in.gcount()));
    if (text.size() > at_most) throw too_large(text.size());
  }
  if (in.bad()) throw FileError(fmt::format("{}: cannot read", path.string()));
  return text;
}

}  // namespace fscil
