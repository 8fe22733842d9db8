#include "core/text_file.h"

#include <fmt/format.h>

#include <fstream>
#include <sstream>

#include "core/report_error.h"

namespace fscil {

std::string read_text_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ReportError(fmt::format("{}: cannot open", path.string()));
  std::stringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

}  // namespace fscil
