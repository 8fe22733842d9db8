#include "protocols/saved_model.h"

#include <fmt/format.h>

#include <fstream>
#include <iterator>

#include "core/error.h"
#include "core/atomic_file.h"

namespace fscil {

void save_model(const std::filesystem::path& path, const SavedModel& model) {
  c10::Dict<std::string, torch::Tensor> state;
  for (const auto& [name, tensor] : model.state) state.insert(name, tensor.detach().to(torch::kCPU).contiguous());
  const SavedModelMetadata& about = model.metadata;
  c10::impl::GenericDict metadata(c10::StringType::get(), c10::AnyType::get());
  metadata.insert("method", about.method);
  metadata.insert("dataset", about.dataset);
  metadata.insert("seed", static_cast<std::int64_t>(about.seed));
  metadata.insert("identity", about.identity);
  metadata.insert("git_commit", about.git_commit);
  metadata.insert("input_shape", c10::List<std::int64_t>(about.input_shape));
  metadata.insert("class_order", c10::List<std::string>(about.class_order));
  c10::impl::GenericDict file(c10::StringType::get(), c10::AnyType::get());
  file.insert("format", std::string(kSavedModelFormat));
  file.insert("metadata", metadata);
  file.insert("state", state);
  const std::vector<char> bytes = torch::pickle_save(file);
  write_file_atomically(path, std::string(bytes.begin(), bytes.end()));
}

SavedModel load_saved_model(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ProtocolError(fmt::format("{}: cannot open the saved model", path.string()));
  const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  c10::IValue value;
  try {
    value = torch::pickle_load(bytes);
  } catch (const std::exception& error) {  // LibTorch's unpickler throws types of its own
    throw ProtocolError(fmt::format("{}: not a saved model ({})", path.string(), error.what()));
  }
  const auto refuse = [&](const std::string& why) {
    throw ProtocolError(fmt::format("{}: not a saved model of {} ({})", path.string(), kSavedModelFormat, why));
  };
  if (!value.isGenericDict()) refuse("expected a dict");
  const c10::impl::GenericDict file = value.toGenericDict();
  for (const char* key : {"format", "metadata", "state"}) {
    if (!file.contains(key)) refuse(fmt::format("no '{}'", key));
  }
  if (!file.at("format").isString() || file.at("format").toStringRef() != kSavedModelFormat) refuse("another format");
  if (!file.at("state").isGenericDict() || !file.at("metadata").isGenericDict()) refuse("state and metadata are dicts");
  SavedModel model;
  for (const auto& entry : file.at("state").toGenericDict()) {
    if (!entry.key().isString() || !entry.value().isTensor()) refuse("'state' holds named tensors");
    model.state[entry.key().toStringRef()] = entry.value().toTensor();
  }
  const c10::impl::GenericDict metadata = file.at("metadata").toGenericDict();
  try {
    SavedModelMetadata& about = model.metadata;
    about.method = metadata.at("method").toStringRef();
    about.dataset = metadata.at("dataset").toStringRef();
    about.seed = static_cast<std::uint64_t>(metadata.at("seed").toInt());
    about.identity = metadata.at("identity").toStringRef();
    about.git_commit = metadata.at("git_commit").toStringRef();
    about.input_shape = metadata.at("input_shape").toIntVector();
    for (const auto& name : metadata.at("class_order").toListRef()) about.class_order.push_back(name.toStringRef());
  } catch (const std::exception& error) {
    refuse(fmt::format("its metadata: {}", error.what()));
  }
  return model;
}

}  // namespace fscil
