#include "datasets/segment_cache.h"

#include <H5Cpp.h>
#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <sstream>

#include "datasets/dataset_catalog.h"
#include "core/error.h"
#include "datasets/hdf5_file.h"
#include "datasets/log_mel_extractor.h"
#include "core/parameter_set.h"
#include "tests/temporary_directory.h"

namespace fscil {
namespace {

// simtex-mini prepared once into a fresh cache directory.
class CachedSimtexMini : public ::testing::Test {
 protected:
  CachedSimtexMini() : built(prepare()) {}
  PreparedDataset prepare() {
    request.cache_dir = directory.path();
    return prepare_dataset("simtex-mini", request, ParameterSet(), log);
  }

  TemporaryDirectory directory;
  DatasetRequest request;
  std::stringstream log;
  const PreparedDataset built;
};

TEST_F(CachedSimtexMini, SecondLoadComesFromTheCacheAndEqualsTheFirst) {
  const SegmentCache cache(directory.path());
  ASSERT_TRUE(std::filesystem::exists(cache.path_for(built.description)));
  const PreparedDataset loaded = prepare();
  EXPECT_EQ(log.str().find("the cache file is rebuilt"), std::string::npos) << log.str();
  EXPECT_EQ(loaded.features.shape, (std::vector<std::int64_t>{600, 5, 64, 24}));
  EXPECT_EQ(loaded.features.values, built.features.values);
  EXPECT_EQ(loaded.segments.signals.values, built.segments.signals.values);
  EXPECT_EQ(loaded.segments.class_index, built.segments.class_index);
  EXPECT_EQ(loaded.segments.recording_ids, built.segments.recording_ids);
  EXPECT_EQ(loaded.segments.context_names, built.segments.context_names);
  ASSERT_EQ(loaded.segments.context_values.size(), built.segments.context_values.size());
  for (std::size_t i = 0; i < loaded.segments.context_values.size(); ++i) {
    EXPECT_FLOAT_EQ(loaded.segments.context_values[i], built.segments.context_values[i]);
  }
}

TEST(SegmentCache, EverySegmentShapingParameterChangesTheKeyAndTheFrontEndDoesNot) {
  DatasetDescription description;
  description.name = "simtex-mini";
  description.source = "simtex seed=1";
  description.segment = {500, 500, 0};
  description.front_end = log_mel_preset("haptex");
  const std::string key = SegmentCache::key_for(description);
  auto changed = description;
  changed.source = "simtex seed=2";
  EXPECT_NE(SegmentCache::key_for(changed), key);
  changed = description;
  changed.segment.hop = 250;
  EXPECT_NE(SegmentCache::key_for(changed), key);
  changed = description;
  changed.segment.length = 250;
  EXPECT_NE(SegmentCache::key_for(changed), key);
  changed = description;
  changed.front_end.scale = MelScale::slaney;  // features are recomputed from the cached segments
  changed.front_end.n_mels = 32;
  EXPECT_EQ(SegmentCache::key_for(changed), key);
}

TEST_F(CachedSimtexMini, FeaturesOnDemandAreLeftToTheRunAndEqualTheStoredOnes) {
  request.features = FeatureStorage::on_demand;
  const PreparedDataset on_demand = prepare();
  EXPECT_TRUE(on_demand.features_on_demand());
  EXPECT_FALSE(built.features_on_demand());
  EXPECT_EQ(on_demand.segments.signals.values, built.segments.signals.values);
  const LogMelExtractor extractor(on_demand.description.front_end);
  EXPECT_EQ(extractor.extract(on_demand.segments.signals).values, built.features.values);
  EXPECT_THROW(parse_feature_storage("disk"), DatasetError);
  EXPECT_EQ(parse_feature_storage("on-demand"), FeatureStorage::on_demand);
}

TEST_F(CachedSimtexMini, ACorruptFileIsReportedAndRebuiltNeverTrusted) {
  const auto path = SegmentCache(directory.path()).path_for(built.description);
  std::filesystem::resize_file(path, std::filesystem::file_size(path) / 2);
  std::string problem;
  EXPECT_FALSE(SegmentCache(directory.path()).load(built.description, &problem).has_value());
  EXPECT_NE(problem.find(path.string()), std::string::npos);
  const PreparedDataset rebuilt = prepare();
  EXPECT_EQ(rebuilt.features.values, built.features.values);
  EXPECT_NE(log.str().find("; the cache file is rebuilt"), std::string::npos);
  EXPECT_TRUE(SegmentCache(directory.path()).load(built.description).has_value());
}

// Rewrites the cache file of `built` with `change` applied to its segments but the digest and
// metadata of the original, as a flipped bit or a hand edit would leave it.
using Tampering = std::function<void(FloatArray& signals, Hdf5Contents& contents)>;
void tamper(const SegmentCache& cache, const PreparedDataset& built, const Tampering& change) {
  const auto path = cache.path_for(built.description);
  Hdf5Contents contents;
  FloatArray signals = read_hdf5_floats(path, "signals", 3);
  contents.floats["signals"] = &signals;
  for (const char* name : {"class_index", "group_index", "recording_index", "recording_split"}) {
    contents.integers[name] = read_hdf5_integers(path, name);
  }
  for (const char* name : {"recording_ids", "channel_names", "class_names"}) contents.strings[name] = read_hdf5_strings(path, name);
  contents.tables["contexts"] = read_hdf5_table(path, "contexts");
  for (const char* name : {"format_version", "key", "digest", "dataset", "source", "sample_rate", "segment_length",
                           "segment_hop", "segment_max_per_recording", "front_end", "context_count",
                           "recording_split_codes"}) {
    contents.attributes[name] = read_hdf5_attribute(path, name);
  }
  change(signals, contents);
  write_hdf5_atomically(path, contents);
}

TEST_F(CachedSimtexMini, AlteredContentsAreNamedAndRebuiltNeverUsedNorACrash) {
  const SegmentCache cache(directory.path());
  const auto path = cache.path_for(built.description);
  const std::vector<std::pair<std::string, Tampering>> faults = {
      {"contents differ from their digest", [](FloatArray& signals, Hdf5Contents&) { signals.values[1234] += 1e-3f; }},
      {"segment 7 has recording 100000, expected 0 to ",
       [](FloatArray&, Hdf5Contents& c) { c.integers["recording_index"][7] = 100000; }},
      {"segment 3 has class 999, expected 0 to 19",
       [](FloatArray&, Hdf5Contents& c) { c.integers["class_index"][3] = 999; }},
      {"segment counts disagree", [](FloatArray&, Hdf5Contents& c) { c.integers["group_index"].pop_back(); }},
      {"segments of 3 channels x 500 samples, expected 5 x 500",
       [](FloatArray& signals, Hdf5Contents&) {
         const std::int64_t n = signals.shape[0], length = signals.shape[2];
         FloatArray fewer({n, 3, length});
         for (std::int64_t i = 0; i < n; ++i) {
           std::copy_n(signals.values.begin() + i * 5 * length, 3 * length, fewer.values.begin() + i * 3 * length);
         }
         signals = std::move(fewer);
       }},
  };
  for (const auto& [expected, change] : faults) {
    tamper(cache, built, change);
    std::string problem;
    EXPECT_FALSE(cache.load(built.description, &problem).has_value()) << expected;
    EXPECT_EQ(problem.rfind(path.string() + ": ", 0), 0u) << problem;
    EXPECT_NE(problem.find(expected), std::string::npos) << problem;
    log.str("");
    const PreparedDataset rebuilt = prepare();
    EXPECT_EQ(rebuilt.segments.signals.values, built.segments.signals.values) << expected;
    EXPECT_EQ(rebuilt.segments.recording_index, built.segments.recording_index) << expected;
    EXPECT_EQ(log.str(), "warning: " + problem + "; the cache file is rebuilt\n");
    EXPECT_TRUE(cache.load(built.description).has_value()) << "rebuilt in place";
  }
}

TEST(Hdf5File, ReadersNameTheFileAndWhatWasExpected) {
  TemporaryDirectory directory;
  const auto path = directory.path() / "data.h5";
  FloatArray matrix({2, 3});
  Hdf5Contents contents;
  contents.floats["signal"] = &matrix;
  contents.integers["labels"] = {1, 2};
  write_hdf5_atomically(path, contents);
  EXPECT_EQ(read_hdf5_floats(path, "signal", 2).shape, (std::vector<std::int64_t>{2, 3}));
  for (const auto& entry : std::filesystem::directory_iterator(directory.path())) {
    EXPECT_EQ(entry.path().filename(), "data.h5") << "no temporary file may remain";
  }
  auto message_of = [](auto&& call) {
    try {
      call();
    } catch (const DatasetError& error) {
      return std::string(error.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message_of([&] { read_hdf5_floats(path, "signal", 3); }).find("has 2 dimensions, expected 3"), std::string::npos);
  EXPECT_NE(message_of([&] { read_hdf5_floats(path, "missing"); }).find("has no dataset 'missing'"), std::string::npos);
  EXPECT_NE(message_of([&] { read_hdf5_floats(path, "labels"); }).find("not floating point"), std::string::npos);
  EXPECT_NE(message_of([&] { read_hdf5_floats(directory.path() / "absent.h5", "signal"); }).find("no such file"),
            std::string::npos);
  std::ofstream(directory.path() / "text.h5") << "not hdf5 at all";
  EXPECT_NE(message_of([&] { read_hdf5_floats(directory.path() / "text.h5", "signal"); }).find("not an HDF5 file"),
            std::string::npos);
  // A few kilobytes declaring 2^40 values (chunked, nothing written): refused before any allocation,
  // where it once ended in "std::bad_alloc" naming nothing.
  const auto huge = directory.path() / "huge.h5";
  {
    H5::H5File file(huge.string(), H5F_ACC_TRUNC);
    const hsize_t dims[2] = {1, hsize_t{1} << 40}, chunk[2] = {1, 1024};
    H5::DSetCreatPropList chunked;
    chunked.setChunk(2, chunk);
    file.createDataSet("signal", H5::PredType::NATIVE_FLOAT, H5::DataSpace(2, dims), chunked);
  }
  EXPECT_LT(std::filesystem::file_size(huge), 100000u);
  EXPECT_NE(message_of([&] { read_hdf5_floats(huge, "signal", 2); })
                .find("huge.h5: dataset 'signal' declares 1 x 1099511627776 values (4398.0 GB), more than this machine's memory"),
            std::string::npos) << message_of([&] { read_hdf5_floats(huge, "signal", 2); });
}

TEST(DatasetCatalog, RealDatasetsWithoutDataRootSayWhatToDownload) {
  try {
    prepare_dataset("lmt108", DatasetRequest{}, ParameterSet(), std::cerr);
    FAIL() << "expected an error";
  } catch (const DatasetError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("--data-root"), std::string::npos);
    EXPECT_NE(message.find("LMT Haptic Texture Database"), std::string::npos);
    EXPECT_NE(message.find("AccelScansComponents/Movement"), std::string::npos);
  }
  EXPECT_THROW(prepare_dataset("cifar100", DatasetRequest{}, ParameterSet(), std::cerr), DatasetError);
}

}  // namespace
}  // namespace fscil
