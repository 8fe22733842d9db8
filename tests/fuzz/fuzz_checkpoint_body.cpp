// What lies behind a checkpoint's length and digest: a torch archive, read field by field. The
// input drives which archive is written (with LibTorch's own writer) and wrapped in a valid
// header, then loaded:
//   - a run state as the runner saves it (save_checkpoint), with any values a run can produce
//     (NaN dispersions and losses, empty sessions): it must load back exactly;
//   - the same fields as any tensors at all (other types, shapes, texts, missing keys, a tensor
//     where the method's archive belongs): each loads or is a ProtocolError.
// Raw bytes of a forged archive reach LibTorch 1.13's unpickler, which trusts the sizes a pickle
// declares (it reads past a tensor's stored bytes, allocates any string length): upstream's
// code, kept out by the digest; fuzz_checkpoint covers the file's own bytes up to that check.
#include <fmt/format.h>
#include <fuzzer/FuzzedDataProvider.h>
#include <torch/torch.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/stable_hash.h"
#include "core/error.h"
#include "metrics/session_accuracy.h"
#include "metrics/session_json.h"
#include "protocols/run_checkpoint.h"
#include "tests/fuzz/fuzz_support.h"
#include "tests/fuzz/fuzz_torch_setup.h"

namespace {

using fscil::fuzz::require;

constexpr const char* kIdentity = "fuzz-run";

double any_double(FuzzedDataProvider& in) {
  const auto bits = in.ConsumeIntegral<std::uint64_t>();
  double value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

std::string name_of(FuzzedDataProvider& in) {
  std::string name = in.ConsumeRandomLengthString(24);
  for (char& c : name) c = "abcdefghijklmnopqrstuvwxyz_.0123456789"[static_cast<unsigned char>(c) % 38];
  return name.empty() ? "x" : name;
}

fscil::RunCheckpoint run_state(FuzzedDataProvider& in) {
  fscil::RunCheckpoint checkpoint;
  checkpoint.identity = kIdentity;
  const int sessions = in.ConsumeIntegralInRange(0, 4);
  for (int s = 0; s < sessions; ++s) {
    fscil::SessionOutcome o;
    o.session = s;
    o.seen_classes = in.ConsumeIntegralInRange(0, 10000);
    for (double* accuracy : {&o.accuracy.base, &o.accuracy.novel, &o.accuracy.current}) {
      *accuracy = in.ConsumeFloatingPointInRange(0.0, 100.0);
    }
    if (s == 0) {  // the base classes alone: no novel class, and they are the current ones
      o.accuracy.novel = 0;
      o.accuracy.current = o.accuracy.base;
    }
    // The joint accuracy weighs the base and the novel samples: it lies between their accuracies.
    const double novel_share = s == 0 ? 0.0 : in.ConsumeProbability<double>();
    o.accuracy.all = std::clamp(o.accuracy.base + novel_share * (o.accuracy.novel - o.accuracy.base),
                                std::min(o.accuracy.base, o.accuracy.novel), std::max(o.accuracy.base, o.accuracy.novel));
    o.accuracy.harmonic = s == 0 ? 0.0 : fscil::harmonic_mean(o.accuracy.base, o.accuracy.novel);
    o.accuracy.samples = in.ConsumeIntegralInRange<std::int64_t>(0, 1'000'000'000);
    o.train_seconds = in.ConsumeFloatingPointInRange(0.0, 1e7);
    o.test_seconds = in.ConsumeFloatingPointInRange(0.0, 1e7);
    o.context_ratio_mean = std::fabs(any_double(in));  // a ratio of spreads: >= 0, infinite or NaN
    o.context_ratio_max = std::fabs(any_double(in));
    const int diagnostics = in.ConsumeIntegralInRange(0, 3);
    for (int d = 0; d < diagnostics; ++d) o.diagnostics[name_of(in)] = any_double(in);
    checkpoint.outcomes.push_back(o);
  }
  checkpoint.elapsed_seconds = in.ConsumeFloatingPointInRange(0.0, 1e7);
  checkpoint.generator.seed(in.ConsumeIntegral<std::uint64_t>());
  checkpoint.generator.discard(in.ConsumeIntegralInRange(0, 700));
  checkpoint.torch_random_state = torch::randint(256, {in.ConsumeIntegralInRange(0, 64)}, torch::kUInt8);
  for (int tensors = in.ConsumeIntegralInRange(0, 3); tensors > 0; --tensors) {
    checkpoint.method_state[name_of(in)] = torch::randn({in.ConsumeIntegralInRange(0, 5), 3});
  }
  return checkpoint;
}

bool same_double(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0 || (std::isnan(a) && std::isnan(b)); }

bool same_outcome(const fscil::SessionOutcome& a, const fscil::SessionOutcome& b) {
  const auto numbers = [](const fscil::SessionOutcome& o) {
    return std::vector<double>{static_cast<double>(o.session), static_cast<double>(o.seen_classes), o.accuracy.all,
                               o.accuracy.base, o.accuracy.novel, o.accuracy.current, o.accuracy.harmonic,
                               static_cast<double>(o.accuracy.samples), o.train_seconds, o.test_seconds,
                               o.context_ratio_mean, o.context_ratio_max};
  };
  const auto x = numbers(a), y = numbers(b);
  bool same = std::equal(x.begin(), x.end(), y.begin(), same_double) && a.diagnostics.size() == b.diagnostics.size();
  for (const auto& [name, value] : a.diagnostics) {
    same = same && b.diagnostics.count(name) > 0 && same_double(value, b.diagnostics.at(name));
  }
  return same;
}

void require_same(const fscil::RunCheckpoint& saved, const fscil::RunCheckpoint& loaded) {
  require(loaded.identity == saved.identity && loaded.outcomes.size() == saved.outcomes.size());
  for (std::size_t s = 0; s < saved.outcomes.size(); ++s) require(same_outcome(saved.outcomes[s], loaded.outcomes[s]));
  require(same_double(saved.elapsed_seconds, loaded.elapsed_seconds) && saved.generator == loaded.generator);
  require(torch::equal(saved.torch_random_state, loaded.torch_random_state));
  require(saved.method_state.size() == loaded.method_state.size());
  for (const auto& [name, tensor] : saved.method_state) require(torch::equal(tensor, loaded.method_state.at(name)));
}

torch::Tensor text_tensor(const std::string& text) {  // as run_checkpoint.cpp stores text
  return torch::tensor(std::vector<std::int64_t>(text.begin(), text.end()), torch::kLong);
}

torch::Tensor any_tensor(FuzzedDataProvider& in) {
  const torch::Dtype dtype =
      in.PickValueInArray({torch::kDouble, torch::kFloat, torch::kLong, torch::kUInt8, torch::kBool});
  std::vector<std::int64_t> shape(in.ConsumeIntegralInRange(0, 3));
  std::int64_t count = 1;
  for (auto& extent : shape) count *= extent = in.ConsumeIntegralInRange(0, 14);
  std::vector<double> values(static_cast<std::size_t>(count));
  for (double& value : values) value = in.ConsumeBool() ? any_double(in) : in.ConsumeIntegralInRange(-3, 300);
  return torch::tensor(values, torch::kDouble).view(shape).to(dtype);
}

// One field: absent, as the runner writes it, another text, or any tensor.
void write_field(torch::serialize::OutputArchive& archive, const std::string& key, const torch::Tensor& proper,
                 FuzzedDataProvider& in) {
  switch (in.ConsumeIntegralInRange(0, 7)) {
    case 0: return;
    case 1: archive.write(key, text_tensor(in.ConsumeRandomLengthString(64))); return;
    case 2: archive.write(key, any_tensor(in)); return;
    default: archive.write(key, proper);
  }
}

std::string any_fields(FuzzedDataProvider& in) {
  const fscil::RunCheckpoint state = run_state(in);
  std::ostringstream generator;
  generator << state.generator;
  // The sessions as the serialiser writes them, or with one character changed.
  std::string sessions = fscil::sessions_json(state.outcomes, fscil::NonFinite::text).dump();
  if (!sessions.empty() && in.ConsumeBool()) {
    sessions[in.ConsumeIntegralInRange<std::size_t>(0, sessions.size() - 1)] = in.ConsumeIntegral<char>();
  }
  torch::serialize::OutputArchive archive;
  write_field(archive, "identity", text_tensor(kIdentity), in);
  write_field(archive, "sessions", text_tensor(sessions), in);
  write_field(archive, "elapsed_seconds", torch::tensor(any_double(in), torch::kDouble), in);
  write_field(archive, "generator", text_tensor(generator.str()), in);
  write_field(archive, "torch_random_state", state.torch_random_state, in);
  switch (in.ConsumeIntegralInRange(0, 3)) {
    case 0: break;
    case 1: archive.write("method", any_tensor(in)); break;
    default: {
      torch::serialize::OutputArchive method;
      for (int t = in.ConsumeIntegralInRange(0, 3); t > 0; --t) method.write(name_of(in), any_tensor(in));
      archive.write("method", method);
    }
  }
  std::ostringstream bytes;
  archive.save_to(bytes);
  return bytes.str();
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  fscil::fuzz::set_up_torch();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace fscil;
  FuzzedDataProvider in(data, size);
  torch::manual_seed(1);  // the tensors drawn below depend on the input alone
  const auto path = fuzz::scratch_folder() / "run.ckpt";
  if (in.ConsumeBool()) {
    const RunCheckpoint saved = run_state(in);
    std::filesystem::remove(path);
    try {
      save_checkpoint(path, saved);
    } catch (const ProtocolError& error) {  // a state name LibTorch could not read back: nothing written
      fuzz::require(std::string(error.what()).find("is a Python keyword") != std::string::npos);
      fuzz::require(!std::filesystem::exists(path));
      return 0;
    }
    require_same(saved, load_checkpoint(path, kIdentity));
    return 0;
  }
  const std::string body = any_fields(in);
  // The header save_checkpoint writes around its body (run_checkpoint.cpp).
  const std::string header = fmt::format("fscil-bench checkpoint 3\n{} {}\n", body.size(), stable_hash(body));
  fuzz::scratch_file("run.ckpt", header + body);
  fuzz::expect_only<ProtocolError>([&] { load_checkpoint(path, kIdentity); });
  return 0;
}
