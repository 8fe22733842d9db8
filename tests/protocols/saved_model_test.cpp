#include "protocols/saved_model.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

#include "core/error.h"
#include "tests/temporary_directory.h"

namespace fscil {
namespace {

SavedModel example_model() {
  return {{{"encoder.conv1.weight", torch::arange(24, torch::kFloat).reshape({2, 3, 4})},
           {"classifier.weight", torch::full({5, 2}, 0.5)},
           {"seen_classes.count", torch::tensor(std::int64_t{15})}},
          {"prototype", "simtex-mini", "method=prototype dataset=simtex-mini seed=3", "abc123", 3, {5, 64, 24},
           {"class 7", "class 2", "class 11"}}};
}

TEST(SavedModel, LibTorchReadsBackEveryNamedTensorAndTheMetadata) {
  TemporaryDirectory directory;
  const auto path = directory.path() / "models" / "run.pt";
  save_model(path, example_model());
  const SavedModel loaded = load_saved_model(path);
  ASSERT_EQ(loaded.state.size(), 3u);
  for (const auto& [name, tensor] : example_model().state) {
    ASSERT_EQ(loaded.state.count(name), 1u) << name;
    EXPECT_TRUE(torch::equal(loaded.state.at(name), tensor)) << name;
  }
  EXPECT_EQ(loaded.metadata.method, "prototype");
  EXPECT_EQ(loaded.metadata.dataset, "simtex-mini");
  EXPECT_EQ(loaded.metadata.seed, 3u);
  EXPECT_EQ(loaded.metadata.identity, "method=prototype dataset=simtex-mini seed=3");
  EXPECT_EQ(loaded.metadata.git_commit, "abc123");
  EXPECT_EQ(loaded.metadata.input_shape, (std::vector<std::int64_t>{5, 64, 24}));
  EXPECT_EQ(loaded.metadata.class_order, (std::vector<std::string>{"class 7", "class 2", "class 11"}));
}

TEST(SavedModel, AFileOfTheFormerLayoutIsRefusedNamingTheFormat) {
  TemporaryDirectory directory;
  const auto path = directory.path() / "old.pt";
  c10::Dict<std::string, torch::Tensor> bare;  // a dict of tensors alone, as files were before metadata
  bare.insert("encoder.conv1.weight", torch::ones({2}));
  const std::vector<char> bytes = torch::pickle_save(bare);
  std::ofstream(path, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  try {
    load_saved_model(path);
    FAIL() << "a model without metadata was read";
  } catch (const ProtocolError& error) {
    EXPECT_EQ(std::string(error.what()), path.string() + ": not a saved model of fscil-bench model 1 (no 'format')");
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

// What a Python user does: torch.load gives the format, the metadata and a dict of named tensors with our names,
// shapes and values.
TEST(SavedModel, PythonTorchLoadReadsADictOfNamedTensors) {
  if (std::system(FSCIL_PYTHON " -c 'import torch' > /dev/null 2>&1") != 0) {
    GTEST_SKIP() << FSCIL_PYTHON << " has no torch (Debian python3-torch, installed by tools/bootstrap.sh)";
  }
  TemporaryDirectory directory;
  const auto path = directory.path() / "run.pt";
  save_model(path, example_model());
  const std::string command =
      std::string(FSCIL_PYTHON) + " -c \"import torch, sys; m = torch.load(sys.argv[1]); d = m['state']; "
      "print(m['format'], m['metadata']['method'], m['metadata']['input_shape'], m['metadata']['class_order'][0]); "
      "[print(k, tuple(v.shape), str(v.dtype), float(v.double().sum())) for k, v in sorted(d.items())]\" " +
      path.string() + " 2>&1";
  FILE* pipe = ::popen(command.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string output;
  char buffer[512];
  while (std::fgets(buffer, sizeof buffer, pipe) != nullptr) output += buffer;
  ASSERT_EQ(::pclose(pipe), 0) << output;
  EXPECT_EQ(output,
            "fscil-bench model 1 prototype [5, 64, 24] class 7\n"
            "classifier.weight (5, 2) torch.float32 5.0\n"
            "encoder.conv1.weight (2, 3, 4) torch.float32 276.0\n"
            "seen_classes.count () torch.int64 15.0\n");
}

}  // namespace
}  // namespace fscil
