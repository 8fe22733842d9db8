// Writes the seed corpus of fuzz_checkpoint with save_checkpoint: `make_checkpoint_seeds CORPUS_DIR`.
// Run by hand after the checkpoint format changes; the seeds are small files kept in the repository.
#include <torch/torch.h>

#include <filesystem>
#include <iostream>
#include <sstream>

#include "metrics/session_accuracy.h"
#include "protocols/run_checkpoint.h"

namespace fs = std::filesystem;

namespace {

fscil::SessionOutcome outcome(int session, int seen_classes) {
  fscil::SessionOutcome o;
  o.session = session;
  o.seen_classes = seen_classes;
  // Session 0 scores the base classes alone; later sessions' harmonic mean is of base and novel.
  o.accuracy = session == 0 ? fscil::SessionAccuracy{70.0, 70.0, 0.0, 70.0, 0.0, 80}
                            : fscil::SessionAccuracy{62.5, 70.0, 40.0, 55.0, fscil::harmonic_mean(70.0, 40.0), 80};
  o.train_seconds = 1.5;
  o.test_seconds = 0.25;
  if (session > 0) o.diagnostics = {{"effective_shots", 4.5}, {"loss", 0.125}};
  return o;
}

// Random states as small as the format allows, so the seeds stay a few KB: an mt19937_64 whose 312
// state words are 0 (its text is still 313 numbers) and a short byte tensor for LibTorch's.
std::mt19937_64 zero_generator() {
  std::string text;
  for (int i = 0; i < 312; ++i) text += "0 ";
  std::istringstream in(text + "312");
  std::mt19937_64 generator;
  in >> generator;
  return generator;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: make_checkpoint_seeds CORPUS_DIR\n";
    return 2;
  }
  const fs::path corpus = argv[1];
  fs::create_directories(corpus / "checkpoint");
  const torch::Tensor torch_state = torch::arange(16, torch::kUInt8);
  const std::vector<fscil::RunCheckpoint> checkpoints = {
      {"fuzz-run", {outcome(0, 3)}, 2.0, {}, zero_generator(), torch_state},
      {"fuzz-run", {outcome(0, 3), outcome(1, 5)}, 4.5,
       {{"encoder.weight", torch::linspace(-1, 1, 6).view({2, 3})}, {"prototypes", torch::ones({5}, torch::kDouble)}},
       zero_generator(), torch_state},
      {"another-run", {outcome(0, 3)}, 1.0, {}, zero_generator(), torch_state}};
  const char* names[] = {"one_session", "two_sessions_with_state", "another_run"};
  for (std::size_t i = 0; i < checkpoints.size(); ++i) {
    fscil::save_checkpoint(corpus / "checkpoint" / (std::string(names[i]) + ".ckpt"), checkpoints[i]);
  }
  return 0;
}
