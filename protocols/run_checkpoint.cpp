#include "protocols/run_checkpoint.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <new>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string_view>

#include "core/json_depth.h"
#include "core/stable_hash.h"
#include "core/error.h"
#include "core/text_file.h"
#include "core/shown_text.h"
#include "core/atomic_file.h"
#include "metrics/session_json.h"

namespace fscil {

namespace {

namespace fs = std::filesystem;

// 2: per-session diagnostics; 3: the finished sessions as metrics/session_json.h writes them.
constexpr const char* kMagicPrefix = "fscil-bench checkpoint ";
constexpr const char* kMagic = "fscil-bench checkpoint 3";

torch::Tensor text_tensor(const std::string& text) {
  return torch::tensor(std::vector<std::int64_t>(text.begin(), text.end()), torch::kLong);
}

std::string tensor_text(const torch::Tensor& tensor) {
  const torch::Tensor values = tensor.to(torch::kLong).contiguous();
  return std::string(values.data_ptr<std::int64_t>(), values.data_ptr<std::int64_t>() + values.numel());
}

// LibTorch stores each name of the method's state as an attribute in TorchScript source, whose
// reader cannot take a Python keyword there ("expected ident but found 'in'"): the part of `name`
// that is one, or "" when there is none.
std::string keyword_part(const std::string& name) {
  static constexpr std::array<std::string_view, 35> kKeywords = {
      "False", "None",   "True",    "and",      "as",   "assert", "async",  "await", "break",
      "class", "continue", "def",   "del",      "elif", "else",   "except", "finally", "for",
      "from",  "global", "if",      "import",   "in",   "is",     "lambda", "nonlocal", "not",
      "or",    "pass",   "raise",   "return",   "try",  "while",  "with",   "yield"};
  std::size_t first = 0;
  while (first <= name.size()) {
    const std::size_t end = std::min(name.find('.', first), name.size());
    const std::string_view part(name.data() + first, end - first);
    if (std::find(kKeywords.begin(), kKeywords.end(), part) != kKeywords.end()) return std::string(part);
    first = end + 1;
  }
  return "";
}

std::string serialize(const RunCheckpoint& checkpoint) {
  for (const auto& entry : checkpoint.method_state) {
    if (const std::string part = keyword_part(entry.first); !part.empty()) {
      throw ProtocolError(fmt::format("method state '{}': '{}' is a Python keyword, which a checkpoint cannot hold "
                                      "(LibTorch could not read it back); rename that module or parameter",
                                      shown_text(entry.first), part));
    }
  }
  torch::serialize::OutputArchive archive;
  archive.write("identity", text_tensor(checkpoint.identity));
  // Exact: a diverged loss's -inf comes back as -inf.
  archive.write("sessions", text_tensor(sessions_json(checkpoint.outcomes, NonFinite::text).dump()));
  archive.write("elapsed_seconds", torch::tensor(checkpoint.elapsed_seconds, torch::kDouble));
  std::ostringstream generator;
  generator << checkpoint.generator;
  archive.write("generator", text_tensor(generator.str()));
  archive.write("torch_random_state", checkpoint.torch_random_state);
  torch::serialize::OutputArchive method;
  for (const auto& [name, tensor] : checkpoint.method_state) method.write(name, tensor);
  archive.write("method", method);
  std::ostringstream bytes;
  archive.save_to(bytes);
  return bytes.str();
}

}  // namespace

RunCheckpoint checkpoint_of_stage(const TrainedStage& stage, std::string identity, double elapsed_seconds) {
  SessionOutcome outcome;
  outcome.train_seconds = stage.seconds;
  outcome.diagnostics = stage.diagnostics;
  outcome.training_log = stage.training_log;
  return {std::move(identity), {outcome}, elapsed_seconds, stage.state, stage.generator, stage.torch_random_state};
}

TrainedStage stage_of_checkpoint(RunCheckpoint checkpoint) {
  if (checkpoint.outcomes.size() != 1) {
    throw ProtocolError(fmt::format("a stage's checkpoint holds one session, this one {}", checkpoint.outcomes.size()));
  }
  SessionOutcome& outcome = checkpoint.outcomes.front();
  return {std::move(checkpoint.method_state), checkpoint.generator, checkpoint.torch_random_state,
          std::move(outcome.training_log), std::move(outcome.diagnostics), outcome.train_seconds};
}

void save_checkpoint(const fs::path& path, const RunCheckpoint& checkpoint) {
  const std::string body = serialize(checkpoint);
  write_file_atomically(path, fmt::format("{}\n{} {}\n", kMagic, body.size(), stable_hash(body)) + body);
}

RunCheckpoint load_checkpoint(const fs::path& path, const std::string& expected_identity) {
  // A folder opens as a stream that reads nothing: say what it is, not that a checkpoint is corrupt.
  if (const std::string why = why_not_a_regular_file(path); !why.empty()) {
    throw ProtocolError(fmt::format("{}: {}, expected a checkpoint file (move it away to start that run over)",
                                    path.string(), why));
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ProtocolError(fmt::format("{}: cannot open the checkpoint", path.string()));
  const auto corrupt = [&] {
    return ProtocolError(fmt::format("{}: corrupt checkpoint (truncated, altered or not a fscil-bench checkpoint); "
                                     "delete it to start that run over", path.string()));
  };
  std::string magic, digest;
  std::size_t length = 0;
  std::getline(in, magic);
  in >> length >> digest;
  in.get();
  // The length comes from the file: a damaged one could ask for terabytes, so it must fit the file
  // before the body is allocated.
  std::error_code size_error;
  if (magic != kMagic && magic.rfind(kMagicPrefix, 0) == 0) {
    throw ProtocolError(fmt::format("{}: {}, this version reads {}; delete it to start that run over", path.string(),
                                    shown_text(magic), kMagic));
  }
  if (magic != kMagic || !in || length > fs::file_size(path, size_error) || size_error) throw corrupt();
  std::string body;
  try {
    body.resize(length);
  } catch (const std::bad_alloc&) {  // a sparse file can claim more than the machine holds
    throw ProtocolError(fmt::format("{}: a checkpoint of {} bytes, more than this machine can hold; delete it to "
                                    "start that run over", path.string(), length));
  }
  if (!in.read(body.data(), static_cast<std::streamsize>(length)) || in.peek() != std::char_traits<char>::eof() ||
      stable_hash(body) != digest) {
    throw corrupt();
  }
  RunCheckpoint checkpoint;
  try {
    torch::serialize::InputArchive archive;
    std::istringstream stream(body);
    archive.load_from(stream);
    // A fresh tensor per read: reading into a defined tensor would copy into its type.
    const auto read = [](torch::serialize::InputArchive& from, const std::string& key) {
      torch::Tensor value;
      from.read(key, value);
      return value;
    };
    checkpoint.identity = tensor_text(read(archive, "identity"));
    if (checkpoint.identity != expected_identity) {
      throw ProtocolError(fmt::format("{}: checkpoint of another run ({}), expected {}", path.string(),
                                      checkpoint.identity, expected_identity));
    }
    try {
      const std::string sessions = tensor_text(read(archive, "sessions"));
      if (json_nests_deeper_than(sessions, kDeepestJson)) throw corrupt();
      checkpoint.outcomes = sessions_from_json(nlohmann::json::parse(sessions),
                                               path.string() + ": corrupt checkpoint, session results");
    } catch (const nlohmann::json::exception& error) {
      throw ProtocolError(fmt::format("{}: corrupt checkpoint, session results: {}", path.string(), error.what()));
    } catch (const Error& error) {  // names the file and the field
      throw ProtocolError(error.what());
    }
    checkpoint.elapsed_seconds = read(archive, "elapsed_seconds").item<double>();
    if (!(checkpoint.elapsed_seconds >= 0 && checkpoint.elapsed_seconds <= kMostSeconds)) throw corrupt();
    std::istringstream generator(tensor_text(read(archive, "generator")));
    generator >> checkpoint.generator;
    checkpoint.torch_random_state = read(archive, "torch_random_state");
    torch::serialize::InputArchive method;
    archive.read("method", method);
    for (const auto& name : method.keys()) checkpoint.method_state[name] = read(method, name);
  } catch (const ProtocolError&) {
    throw;
  } catch (const c10::Error& error) {
    throw ProtocolError(fmt::format("{}: corrupt checkpoint ({})", path.string(), error.what_without_backtrace()));
  } catch (const std::exception& error) {  // LibTorch's TorchScript importer throws types of its own too
    throw ProtocolError(fmt::format("{}: corrupt checkpoint ({})", path.string(), shown_text(error.what())));
  }
  return checkpoint;
}

}  // namespace fscil
