#include "protocols/run_checkpoint.h"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "core/stable_hash.h"
#include "core/error.h"
#include "core/shown_text.h"
#include "core/atomic_file.h"
#include "core/number_text.h"

namespace fscil {

namespace {

namespace fs = std::filesystem;

constexpr const char* kMagic = "fscil-bench checkpoint 2";  // 2: per-session diagnostics
constexpr int kOutcomeFields = 12;

torch::Tensor text_tensor(const std::string& text) {
  return torch::tensor(std::vector<std::int64_t>(text.begin(), text.end()), torch::kLong);
}

std::string tensor_text(const torch::Tensor& tensor) {
  const torch::Tensor values = tensor.to(torch::kLong).contiguous();
  return std::string(values.data_ptr<std::int64_t>(), values.data_ptr<std::int64_t>() + values.numel());
}

torch::Tensor outcome_rows(const std::vector<SessionOutcome>& outcomes) {
  std::vector<double> values;
  for (const auto& o : outcomes) {
    values.insert(values.end(), {static_cast<double>(o.session), static_cast<double>(o.seen_classes), o.accuracy.all,
                                 o.accuracy.base, o.accuracy.novel, o.accuracy.current, o.accuracy.harmonic,
                                 static_cast<double>(o.accuracy.samples), o.train_seconds, o.test_seconds,
                                 o.context_ratio_mean, o.context_ratio_max});
  }
  return torch::tensor(values, torch::kDouble).view({static_cast<std::int64_t>(outcomes.size()), kOutcomeFields});
}

// Whether `rows` is what outcome_rows writes: any other shape would be read past its end, and a
// session, class or sample count that is no whole number in range converted with undefined behaviour.
bool readable_outcome_rows(const torch::Tensor& rows) {
  if (rows.dim() != 2 || rows.size(1) != kOutcomeFields || rows.scalar_type() != torch::kDouble) return false;
  const auto whole_below_power_of_two = [](double value, int bits) {
    return value >= 0 && value < std::ldexp(1.0, bits) && value == std::floor(value);
  };
  const torch::Tensor contiguous = rows.contiguous();
  const auto v = contiguous.accessor<double, 2>();
  for (std::int64_t r = 0; r < rows.size(0); ++r) {
    if (!whole_below_power_of_two(v[r][0], 31) || !whole_below_power_of_two(v[r][1], 31) ||
        !whole_below_power_of_two(v[r][7], 63)) {
      return false;
    }
  }
  return true;
}

std::vector<SessionOutcome> outcomes_of(const torch::Tensor& rows) {
  std::vector<SessionOutcome> outcomes;
  const torch::Tensor contiguous = rows.contiguous();
  const auto v = contiguous.accessor<double, 2>();
  for (std::int64_t r = 0; r < rows.size(0); ++r) {
    SessionOutcome o;
    o.session = static_cast<int>(v[r][0]);
    o.seen_classes = static_cast<int>(v[r][1]);
    o.accuracy.all = v[r][2];
    o.accuracy.base = v[r][3];
    o.accuracy.novel = v[r][4];
    o.accuracy.current = v[r][5];
    o.accuracy.harmonic = v[r][6];
    o.accuracy.samples = static_cast<std::int64_t>(v[r][7]);
    o.train_seconds = v[r][8];
    o.test_seconds = v[r][9];
    o.context_ratio_mean = v[r][10];
    o.context_ratio_max = v[r][11];
    outcomes.push_back(o);
  }
  return outcomes;
}

// One line per diagnostic: session, name and value (written exactly, as %.17g).
std::string diagnostics_text(const std::vector<SessionOutcome>& outcomes) {
  std::string text;
  for (const auto& o : outcomes) {
    for (const auto& [name, value] : o.diagnostics) text += fmt::format("{}\t{}\t{:.17g}\n", o.session, name, value);
  }
  return text;
}

// False when a line does not name a finished session, a name and a value.
bool read_diagnostics(const std::string& text, std::vector<SessionOutcome>& outcomes) {
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    std::istringstream fields(line);
    std::size_t session = 0;
    std::string name, value;
    if (!(fields >> session >> name >> value) || session >= outcomes.size()) return false;
    // Not >>: a diverged loss is written as nan or inf, and >> refuses those and subnormals.
    const auto parsed = parse_number<double>(value);
    if (!parsed) return false;
    outcomes[session].diagnostics[name] = *parsed;
  }
  return true;
}

// One line per logged value: session, stage, epoch, name and value, tab-separated (stages hold spaces).
std::string training_log_text(const std::vector<SessionOutcome>& outcomes) {
  std::string text;
  for (const auto& o : outcomes) {
    for (const auto& row : o.training_log) {
      for (const auto& [name, value] : row.values) {
        text += fmt::format("{}\t{}\t{}\t{}\t{:.17g}\n", o.session, row.stage, row.epoch, name, value);
      }
    }
  }
  return text;
}

// False when a line does not name a finished session, a stage, an epoch, a name and a value.
bool read_training_log(const std::string& text, std::vector<SessionOutcome>& outcomes) {
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    std::vector<std::string> fields;
    std::istringstream cells(line);
    for (std::string field; std::getline(cells, field, '\t');) fields.push_back(field);
    if (fields.size() != 5) return false;
    const auto session = parse_number<std::size_t>(fields[0]);
    const auto epoch = parse_number<int>(fields[2]);
    const auto value = parse_number<double>(fields[4]);
    if (!session || *session >= outcomes.size() || !epoch || !value) return false;
    auto& log = outcomes[*session].training_log;
    // Values of one epoch are consecutive lines.
    if (log.empty() || log.back().stage != fields[1] || log.back().epoch != *epoch) log.push_back({fields[1], *epoch, {}});
    log.back().values[fields[3]] = *value;
  }
  return true;
}

std::string serialize(const RunCheckpoint& checkpoint) {
  torch::serialize::OutputArchive archive;
  archive.write("identity", text_tensor(checkpoint.identity));
  archive.write("outcomes", outcome_rows(checkpoint.outcomes));
  archive.write("diagnostics", text_tensor(diagnostics_text(checkpoint.outcomes)));
  archive.write("training_log", text_tensor(training_log_text(checkpoint.outcomes)));
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

void save_checkpoint(const fs::path& path, const RunCheckpoint& checkpoint) {
  const std::string body = serialize(checkpoint);
  write_file_atomically(path, fmt::format("{}\n{} {}\n", kMagic, body.size(), stable_hash(body)) + body);
}

RunCheckpoint load_checkpoint(const fs::path& path, const std::string& expected_identity) {
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
  if (magic != kMagic || !in || length > fs::file_size(path, size_error) || size_error) throw corrupt();
  std::string body(length, '\0');
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
    const torch::Tensor rows = read(archive, "outcomes");
    if (!readable_outcome_rows(rows)) {
      throw ProtocolError(fmt::format("{}: corrupt checkpoint (session results are not N x {} values with whole "
                                      "session, class and sample counts)", path.string(), kOutcomeFields));
    }
    checkpoint.outcomes = outcomes_of(rows);
    if (!read_diagnostics(tensor_text(read(archive, "diagnostics")), checkpoint.outcomes)) {
      throw ProtocolError(fmt::format("{}: corrupt checkpoint (a diagnostics line names no finished session)",
                                      path.string()));
    }
    // Checkpoints and cached bases written before the log was kept have none.
    if (torch::Tensor log; archive.try_read("training_log", log) &&
                           !read_training_log(tensor_text(log), checkpoint.outcomes)) {
      throw ProtocolError(fmt::format("{}: corrupt checkpoint (a training log line is not session, stage, epoch, "
                                      "name and value of a finished session)", path.string()));
    }
    checkpoint.elapsed_seconds = read(archive, "elapsed_seconds").item<double>();
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
