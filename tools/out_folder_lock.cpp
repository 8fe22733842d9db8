#include "tools/out_folder_lock.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "protocols/protocol_error.h"

namespace fscil {

OutFolderLock::OutFolderLock(const std::filesystem::path& folder) {
  std::error_code error;
  std::filesystem::create_directories(folder, error);
  if (error) throw ProtocolError(fmt::format("--out {}: cannot create the folder ({})", folder.string(), error.message()));
  descriptor_ = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (descriptor_ < 0) {
    throw ProtocolError(fmt::format("--out {}: cannot open the folder ({})", folder.string(), std::strerror(errno)));
  }
  if (::flock(descriptor_, LOCK_EX | LOCK_NB) != 0) {
    ::close(descriptor_);
    throw ProtocolError(fmt::format("--out {}: another fscil-bench command is writing there; wait for it or use "
                                    "another --out", folder.string()));
  }
}

OutFolderLock::~OutFolderLock() { ::close(descriptor_); }

}  // namespace fscil
