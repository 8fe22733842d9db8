#include "protocols/saved_model.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

#include "core/error.h"
#include "tests/temporary_directory.h"

namespace fscil {
namespace {

MethodState example_state() {
  return {{"encoder.conv1.weight", torch::arange(24, torch::kFloat).reshape({2, 3, 4})},
          {"classifier.weight", torch::full({5, 2}, 0.5)},
          {"seen_classes", torch::tensor(std::int64_t{15})}};
}

TEST(SavedModel, LibTorchReadsBackEveryNamedTensor) {
  TemporaryDirectory directory;
  const auto path = directory.path() / "models" / "run.pt";
  save_model(path, example_state());
  const MethodState loaded = load_saved_model(path);
  ASSERT_EQ(loaded.size(), 3u);
  for (const auto& [name, tensor] : example_state()) {
    ASSERT_EQ(loaded.count(name), 1u) << name;
    EXPECT_TRUE(torch::equal(loaded.at(name), tensor)) << name;
  }
}

TEST(SavedModel, APlainFileIsRefusedNamingIt) {
  TemporaryDirectory directory;
  const auto path = directory.path() / "run.pt";
  std::ofstream(path) << "not a model";
  try {
    load_saved_model(path);
    FAIL() << "a text file was read as a model";
  } catch (const ProtocolError& error) {
    EXPECT_NE(std::string(error.what()).find(path.string() + ": not a saved model"), std::string::npos) << error.what();
  }
}

// What a Python user does: torch.load gives a dict of named tensors with our names, shapes and values.
TEST(SavedModel, PythonTorchLoadReadsADictOfNamedTensors) {
  if (std::system(FSCIL_PYTHON " -c 'import torch' > /dev/null 2>&1") != 0) {
    GTEST_SKIP() << FSCIL_PYTHON << " has no torch (Debian python3-torch, installed by tools/bootstrap.sh)";
  }
  TemporaryDirectory directory;
  const auto path = directory.path() / "run.pt";
  save_model(path, example_state());
  const std::string command =
      std::string(FSCIL_PYTHON) + " -c \"import torch, sys; d = torch.load(sys.argv[1]); "
      "print(type(d).__name__); "
      "[print(k, tuple(v.shape), str(v.dtype), float(v.double().sum())) for k, v in sorted(d.items())]\" " +
      path.string() + " 2>&1";
  FILE* pipe = ::popen(command.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string output;
  char buffer[512];
  while (std::fgets(buffer, sizeof buffer, pipe) != nullptr) output += buffer;
  ASSERT_EQ(::pclose(pipe), 0) << output;
  EXPECT_EQ(output,
            "dict\n"
            "classifier.weight (5, 2) torch.float32 5.0\n"
            "encoder.conv1.weight (2, 3, 4) torch.float32 276.0\n"
            "seen_classes () torch.int64 15.0\n");
}

}  // namespace
}  // namespace fscil
