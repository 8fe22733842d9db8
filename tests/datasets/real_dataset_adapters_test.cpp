// Each real-data adapter reads a small tree written in its dataset's real layout.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <sstream>

#include "datasets/dataset_catalog.h"
#include "core/error.h"
#include "core/parameter_set.h"
#include "tests/fixtures/dataset_fixtures.h"
#include "tests/datasets/prepare_from_root.h"
#include "tests/temporary_directory.h"

namespace fscil {
namespace {

namespace fs = std::filesystem;

std::vector<std::int64_t> feature_shape(const PreparedDataset& dataset) {
  return {dataset.features.shape.begin() + 1, dataset.features.shape.end()};
}

int count_split(const PreparedDataset& dataset, SplitHint hint) {
  int count = 0;
  for (SplitHint split : dataset.segments.recording_split) count += split == hint;
  return count;
}

TEST(Lmt108Adapter, ReadsMaterialsGroupsAndTheDatabasesOwnTestRecordings) {
  TemporaryDirectory root;
  write_lmt108_fixture(root.path(), {});
  const PreparedDataset dataset = prepare_from_root("lmt108", root.path());
  EXPECT_EQ(dataset.description.class_names,
            (std::vector<std::string>{"G1EpoxyRasterPlate", "G1NylonBag", "G2BrickRough"}));
  EXPECT_EQ(dataset.description.group_names, (std::vector<std::string>{"G1", "G2"}));
  EXPECT_EQ(dataset.description.channel_names, (std::vector<std::string>{"accel_x", "accel_y", "accel_z"}));
  // 3 materials x (3 train + 2 test) recordings x two 8 000-sample segments in 16 500 samples.
  EXPECT_EQ(dataset.segments.count(), 30);
  EXPECT_EQ(feature_shape(dataset), (std::vector<std::int64_t>{3, 64, 493}));
  EXPECT_EQ(count_split(dataset, SplitHint::train), 9);
  EXPECT_EQ(count_split(dataset, SplitHint::test), 6);
  EXPECT_EQ(dataset.segments.group_index, (std::vector<int>{0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
                                                            1, 1, 1, 1, 1, 1, 1, 1, 1, 1}));
  // The X channel of the first segment is the first 8 000 values of the X file.
  const auto first_x = read_text(root.path() / "AccelScansComponents/Movement/Testing/G1EpoxyRasterPlate_Movement_X_test1.txt");
  EXPECT_EQ(dataset.segments.recording_ids[0], "G1EpoxyRasterPlate_test1");
  EXPECT_FLOAT_EQ(dataset.segments.signals.values[0], std::stof(first_x.substr(0, first_x.find('\n'))));
}

TEST(Lmt108Adapter, AddsFrictionAndSoundChannelsWhenAsked) {
  TemporaryDirectory root;
  Lmt108Fixture fixture;
  fixture.friction = fixture.sound = true;
  write_lmt108_fixture(root.path(), fixture);
  ParameterSet params;
  params.set("lmt108_signals", "accel+friction+sound");
  const PreparedDataset dataset = prepare_from_root("lmt108", root.path(), params);
  EXPECT_EQ(dataset.description.channel_names,
            (std::vector<std::string>{"accel_x", "accel_y", "accel_z", "friction", "sound"}));
  EXPECT_EQ(feature_shape(dataset), (std::vector<std::int64_t>{5, 64, 493}));
  // The fixture writes the same tone to every channel; WAV keeps it to 16-bit precision.
  const auto& signals = dataset.segments.signals;
  EXPECT_NEAR(signals.values[3 * 8000 + 123], signals.values[123], 1e-5);
  EXPECT_NEAR(signals.values[4 * 8000 + 123], signals.values[123], 1e-4);
}

TEST(HaptexAdapter, ReadsTheFolderFormatWithHaptexShapes) {
  TemporaryDirectory root;
  write_haptex_fixture(root.path(), {});
  const PreparedDataset dataset = prepare_from_root("haptex", root.path());
  EXPECT_EQ(dataset.description.class_names.size(), 4u);
  EXPECT_EQ(dataset.description.class_names[3], "fabric03");
  EXPECT_EQ(dataset.description.group_names, (std::vector<std::string>{"weave0", "weave1"}));
  EXPECT_EQ(dataset.segments.count(), 4 * 4 * 2);
  EXPECT_EQ(feature_shape(dataset), (std::vector<std::int64_t>{5, 64, 24}));
  EXPECT_EQ(dataset.description.sessions.base_classes, 75);
  // Channel 1 is normal_force = 1 + tone / 2 in the fixture.
  const auto& s = dataset.segments.signals;
  EXPECT_NEAR(s.values[500 + 7], 1 + s.values[7] / 2, 1e-4);
}

TEST(FolderAdapter, ReadsContextsSplitsAndOneTxtPerChannel) {
  TemporaryDirectory root;
  write_text(root.path() / "dataset.json", R"({"name": "lab", "sample_rate": 1000, "channels": ["force", "accel"],
    "segment_seconds": 0.25, "hop_seconds": 0.125, "sessions": {"base_classes": 1, "way": 1, "shot": 1, "sessions": 2}})");
  std::string manifest = "file,class,group,recording,split,context\n";
  for (int c = 0; c < 2; ++c) {
    for (int r = 0; r < 3; ++r) {
      const std::string stem = fmt::format("c{}r{}", c, r);
      std::string force, accel;
      for (int t = 0; t < 500; ++t) {
        force += fmt::format("{}\n", c + 0.001 * t + 0.1 * r);  // each recording its own signal, one
        // channel the same in all
        accel += fmt::format("{}\n", -c - 0.001 * t);
      }
      write_text(root.path() / (stem + "_force.txt"), force);
      write_text(root.path() / (stem + "_accel.txt"), accel);
      manifest += fmt::format("{0}_force.txt;{0}_accel.txt,cls{1},g,{0},{2},speed={3};device=2\n", stem, c,
                              r == 2 ? "test" : "", r + 1);
    }
  }
  write_text(root.path() / "manifest.csv", manifest);
  const PreparedDataset dataset = prepare_from_root("folder", root.path());
  EXPECT_EQ(dataset.description.name, "lab");
  // 500 samples, 250-sample segments every 125: 3 per recording.
  EXPECT_EQ(dataset.segments.count(), 2 * 3 * 3);
  EXPECT_EQ(feature_shape(dataset), (std::vector<std::int64_t>{2, 64, 8}));
  EXPECT_EQ(dataset.segments.context_names, (std::vector<std::string>{"device", "speed"}));
  EXPECT_EQ(dataset.segments.context_values[2 * 5 + 1], 3.0);  // recording c1r2: speed 3
  EXPECT_EQ(count_split(dataset, SplitHint::test), 2);
  EXPECT_EQ(dataset.description.sessions.sessions, 2);
  // Segment 1 of c0r0 starts at sample 125; the accel channel follows the force channel.
  const auto& s = dataset.segments.signals;
  EXPECT_NEAR(s.values[1 * 500 + 0], 0.125, 1e-6);
  EXPECT_NEAR(s.values[1 * 500 + 250], -0.125, 1e-6);
}

TEST(AudioAdapters, Ls100ReadsListedSplitsAndRepeatsMonoToThreeChannels) {
  TemporaryDirectory root;
  write_ls100_fixture(root.path(), {});
  const PreparedDataset dataset = prepare_from_root("ls100", root.path());
  EXPECT_EQ(dataset.description.class_names, (std::vector<std::string>{"speaker100", "speaker101", "speaker102",
                                                                       "speaker103"}));
  EXPECT_EQ(dataset.segments.count(), 4 * 8);  // one segment per 2 s clip
  EXPECT_EQ(feature_shape(dataset), (std::vector<std::int64_t>{1, 128, 178}));
  EXPECT_EQ(dataset.description.channel_repeat, 3);
  EXPECT_EQ(count_split(dataset, SplitHint::train), 20);
  EXPECT_EQ(count_split(dataset, SplitHint::validation), 4);
  EXPECT_EQ(count_split(dataset, SplitHint::test), 8);
}

TEST(AudioAdapters, Ns100MapsInstrumentsThroughTheVocabulary) {
  TemporaryDirectory root;
  write_ns100_fixture(root.path(), {3, 2, 1, 1});
  const PreparedDataset dataset = prepare_from_root("ns100", root.path());
  EXPECT_EQ(dataset.description.class_names, (std::vector<std::string>{"instrument_0", "instrument_1", "instrument_2"}));
  EXPECT_EQ(dataset.segments.count(), 3 * 4);
  EXPECT_EQ(feature_shape(dataset), (std::vector<std::int64_t>{1, 128, 63}));
  EXPECT_EQ(dataset.segments.class_index.back(), 2);
}

}  // namespace
}  // namespace fscil
