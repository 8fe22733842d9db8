#include "protocols/saved_model.h"

#include <fmt/format.h>

#include <fstream>
#include <iterator>

#include "core/error.h"
#include "core/atomic_file.h"

namespace fscil {

void save_model(const std::filesystem::path& path, const MethodState& state) {
  c10::Dict<std::string, torch::Tensor> dict;
  for (const auto& [name, tensor] : state) dict.insert(name, tensor.detach().to(torch::kCPU).contiguous());
  const std::vector<char> bytes = torch::pickle_save(dict);
  write_file_atomically(path, std::string(bytes.begin(), bytes.end()));
}

MethodState load_saved_model(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ProtocolError(fmt::format("{}: cannot open the saved model", path.string()));
  const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  c10::IValue value;
  try {
    value = torch::pickle_load(bytes);
  } catch (const std::exception& error) {  // LibTorch's unpickler throws types of its own
    throw ProtocolError(fmt::format("{}: not a saved model ({})", path.string(), error.what()));
  }
  if (!value.isGenericDict()) throw ProtocolError(fmt::format("{}: expected a dict of named tensors", path.string()));
  MethodState state;
  for (const auto& entry : value.toGenericDict()) {
    if (!entry.key().isString() || !entry.value().isTensor()) {
      throw ProtocolError(fmt::format("{}: expected a dict of named tensors", path.string()));
    }
    state[entry.key().toStringRef()] = entry.value().toTensor();
  }
  return state;
}

}  // namespace fscil
