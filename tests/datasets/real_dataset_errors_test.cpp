// Every malformed variant of a real dataset gets one DatasetError naming the file (and line or
// field) and what was expected; a failed load leaves the feature cache as it was.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <map>
#include <sstream>

#include "datasets/dataset_catalog.h"
#include "core/error.h"
#include "datasets/readers/text_table.h"
#include "datasets/readers/wav_file.h"
#include "datasets/segment_cache.h"
#include "core/parameter_set.h"
#include "tests/fixtures/dataset_fixtures.h"
#include "tests/datasets/prepare_from_root.h"
#include "tests/temporary_directory.h"

namespace fscil {
namespace {

namespace fs = std::filesystem;

// The message of the DatasetError that loading `name` from `root` raises ("" if none).
std::string load_error(const std::string& name, const fs::path& root, const ParameterSet& params = {},
                       const fs::path& cache = {}) {
  try {
    prepare_from_root(name, root, params, cache);
  } catch (const DatasetError& error) {
    return error.what();
  }
  return "";
}

#define EXPECT_MENTIONS(message, fragment) EXPECT_NE((message).find(fragment), std::string::npos) << (message)

void replace_in(const fs::path& file, const std::string& from, const std::string& to) {
  std::string text = read_text(file);
  const auto at = text.find(from);
  ASSERT_NE(at, std::string::npos) << from;
  text.replace(at, from.size(), to);
  write_text(file, text);
}

class Lmt108Errors : public ::testing::Test {
 protected:
  Lmt108Errors() { write_lmt108_fixture(root.path(), {}); }
  fs::path accel(const std::string& name) const { return root.path() / "AccelScansComponents/Movement" / name; }
  TemporaryDirectory root;
};

TEST_F(Lmt108Errors, MissingFolderNamesItAndTheLayout) {
  fs::remove_all(accel("Testing"));
  const std::string message = load_error("lmt108", root.path());
  EXPECT_MENTIONS(message, "Movement/Testing: no such folder");
  EXPECT_MENTIONS(message, "<Material>_Movement_{X,Y,Z}");
}

TEST_F(Lmt108Errors, MissingAxisFileIsNamed) {
  fs::remove(accel("Training/G1NylonBag_Movement_Y_train2.txt"));
  EXPECT_MENTIONS(load_error("lmt108", root.path()), "G1NylonBag_Movement_Y_train2.txt: no such file");
}

TEST_F(Lmt108Errors, NonNumericValueNamesFileAndLine) {
  replace_in(accel("Training/G1NylonBag_Movement_Z_train3.txt"), "\n", "\nabc\n");
  EXPECT_MENTIONS(load_error("lmt108", root.path()), "G1NylonBag_Movement_Z_train3.txt:2: 'abc' is not a number");
}

TEST_F(Lmt108Errors, NanOrInfIsRefused) {
  replace_in(accel("Testing/G2BrickRough_Movement_X_test2.txt"), "\n", "\nnan\n");
  EXPECT_MENTIONS(load_error("lmt108", root.path()), "G2BrickRough_Movement_X_test2.txt:2: nan found, expected a finite");
  replace_in(accel("Testing/G2BrickRough_Movement_X_test2.txt"), "nan", "-inf");
  EXPECT_MENTIONS(load_error("lmt108", root.path()), "-inf found");
}

TEST_F(Lmt108Errors, SeveralValuesOnALineAreAWrongColumnCount) {
  replace_in(accel("Training/G1NylonBag_Movement_X_train1.txt"), "\n", ",0.5\n");
  EXPECT_MENTIONS(load_error("lmt108", root.path()), "G1NylonBag_Movement_X_train1.txt:1: '");
  EXPECT_MENTIONS(load_error("lmt108", root.path()), "expected one number per line");
}

TEST_F(Lmt108Errors, RecordingShorterThanASegmentIsNamed) {
  write_text(accel("Training/G1NylonBag_Movement_X_train1.txt"), "0.1\n0.2\n");
  write_text(accel("Training/G1NylonBag_Movement_Y_train1.txt"), "0.1\n0.2\n");
  write_text(accel("Training/G1NylonBag_Movement_Z_train1.txt"), "0.1\n0.2\n");
  EXPECT_MENTIONS(load_error("lmt108", root.path()),
                  "G1NylonBag_Movement_X_train1.txt: 2 samples, shorter than one segment of 8000 samples");
}

TEST_F(Lmt108Errors, AxesOfDifferentLengthsAreRefused) {
  replace_in(accel("Training/G1NylonBag_Movement_Z_train1.txt"), "\n", "\n0.25\n");
  EXPECT_MENTIONS(load_error("lmt108", root.path()), "G1NylonBag_Movement_Z_train1.txt: 16501 samples, expected 16500");
}

TEST_F(Lmt108Errors, AskedForFrictionThatIsNotThere) {
  ParameterSet params;
  params.set("lmt108_signals", "accel+friction");
  EXPECT_MENTIONS(load_error("lmt108", root.path(), params), "FricScans: no such folder");
}

TEST(HaptexErrors, DatasetJsonMissingOrContradictingHaptex) {
  TemporaryDirectory root;
  write_haptex_fixture(root.path(), {});
  replace_in(root.path() / "dataset.json", "1000", "2000");
  EXPECT_MENTIONS(load_error("haptex", root.path()), "dataset.json: field 'sample_rate' is 2000, haptex expects 1000");
  fs::remove(root.path() / "dataset.json");
  EXPECT_MENTIONS(load_error("haptex", root.path()), "dataset.json: no such file");
}

TEST(HaptexErrors, BadJsonAndMissingFieldsAreNamed) {
  TemporaryDirectory root;
  write_text(root.path() / "dataset.json", "{\"name\": \"lab\", ");
  EXPECT_MENTIONS(load_error("folder", root.path()), "dataset.json: not JSON (");
  write_text(root.path() / "dataset.json", R"({"name": "lab", "sample_rate": 1000})");
  EXPECT_MENTIONS(load_error("folder", root.path()), "dataset.json: field 'channels' missing, expected a list of names");
  write_text(root.path() / "dataset.json", R"({"name": "lab", "sample_rate": "fast", "channels": ["a"]})");
  EXPECT_MENTIONS(load_error("folder", root.path()), "dataset.json: field 'sample_rate': expected a number");
}

TEST(HaptexErrors, NonsenseValuesInDatasetJsonAreNamed) {
  TemporaryDirectory root;
  const std::string head = R"({"name": "lab", "segment_seconds": 0.5, )";
  write_text(root.path() / "dataset.json", head + R"("sample_rate": NaN, "channels": ["a"]})");
  EXPECT_MENTIONS(load_error("folder", root.path()), "dataset.json: not JSON (");
  write_text(root.path() / "dataset.json", head + R"("sample_rate": -1000, "channels": ["a"]})");
  EXPECT_MENTIONS(load_error("folder", root.path()), "dataset.json: field 'sample_rate': expected a number in (0, 10000000]");
  write_text(root.path() / "dataset.json", head + R"("sample_rate": 1000, "channels": ["x", "y", "x"]})");
  EXPECT_MENTIONS(load_error("folder", root.path()),
                  "dataset.json: field 'channels': expected a list of distinct names ('x' is listed twice)");
  write_text(root.path() / "dataset.json",
             head + R"("sample_rate": 1000, "channels": ["a"], "max_segments_per_recording": -3})");
  EXPECT_MENTIONS(load_error("folder", root.path()),
                  "dataset.json: field 'max_segments_per_recording': expected an integer >= 0");
  write_text(root.path() / "dataset.json",
             head + R"("sample_rate": 1000, "channels": ["a"], "front_end": {"n_mels": 6.5}})");
  EXPECT_MENTIONS(load_error("folder", root.path()), "dataset.json: field 'front_end.n_mels': expected an integer in [1, 1024], found 6.5");
}

class HaptexManifestErrors : public ::testing::Test {
 protected:
  HaptexManifestErrors() { write_haptex_fixture(root.path(), {}); }
  fs::path manifest() const { return root.path() / "manifest.csv"; }
  fs::path recording(int c, int r) const { return root.path() / fmt::format("recordings/fabric{:02d}_{}.csv", c, r); }
  TemporaryDirectory root;
};

TEST_F(HaptexManifestErrors, ManifestNamingAMissingFile) {
  fs::remove(recording(2, 1));
  const std::string message = load_error("haptex", root.path());
  EXPECT_MENTIONS(message, "manifest.csv:");
  EXPECT_MENTIONS(message, "fabric02_1.csv: no such file");
}

// What a name is when it is no file: a folder, a FIFO (whose reading would block), a loop of links.
TEST_F(HaptexManifestErrors, ARecordingThatIsNoRegularFileSaysWhatItIs) {
  const fs::path file = recording(2, 1);
  fs::remove(file);
  fs::create_directory(file);
  EXPECT_MENTIONS(load_error("haptex", root.path()), "fabric02_1.csv: a folder, not a file");
  fs::remove(file);
  ASSERT_EQ(::mkfifo(file.c_str(), 0644), 0);
  EXPECT_MENTIONS(load_error("haptex", root.path()), "fabric02_1.csv: a FIFO, not a regular file");
  fs::remove(file);
  fs::create_symlink(file.filename(), file);
  EXPECT_MENTIONS(load_error("haptex", root.path()), "fabric02_1.csv: a loop of symbolic links");
  fs::remove(file);
  fs::create_symlink("absent.csv", file);
  EXPECT_MENTIONS(load_error("haptex", root.path()), "fabric02_1.csv: a symbolic link to nothing");
}

// Found by fuzzing: a name longer than the file system takes escaped as std::filesystem_error.
TEST_F(HaptexManifestErrors, AFileNameNoFileSystemTakesIsUnreadable) {
  replace_in(manifest(), "recordings/fabric02_1.csv,", "recordings/" + std::string(300, 'x') + ".csv,");
  const std::string message = load_error("haptex", root.path());
  EXPECT_MENTIONS(message, "manifest.csv:11: file ");
  EXPECT_MENTIONS(message, "bytes in all): unreadable (File name too long)");
}

TEST_F(HaptexManifestErrors, ManifestRowWithAWrongColumnCount) {
  replace_in(manifest(), "fabric01_rec2\n", "fabric01_rec2,extra\n");
  EXPECT_MENTIONS(load_error("haptex", root.path()), "manifest.csv:8: 5 fields, expected 4");
}

TEST_F(HaptexManifestErrors, OneFileUnderTwoRecordingsOrClassesWhateverItsSpelling) {
  // Under another recording id of the same class (the two could land in train and test).
  replace_in(manifest(), "recordings/fabric01_2.csv,", "recordings/../recordings/fabric01_1.csv,");
  EXPECT_MENTIONS(load_error("haptex", root.path()),
                  "manifest.csv:8: file " + (root.path() / "recordings/../recordings/fabric01_1.csv").string() +
                      " already listed on line 7 (recording 'fabric01_rec1'); a file belongs to one recording");
  // Under another class.
  replace_in(manifest(), "recordings/../recordings/fabric01_1.csv,", "recordings/fabric01_2.csv,");
  replace_in(manifest(), "recordings/fabric02_0.csv,", "recordings/fabric01_0.csv,");
  EXPECT_MENTIONS(load_error("haptex", root.path()), "manifest.csv:10: file " + (root.path() / "recordings/fabric01_0.csv").string() +
                      " already listed on line 6 (recording 'fabric01_rec0')");
}

TEST_F(HaptexManifestErrors, LeakageACopyOrALinkCouldHideIsRefused) {
  const std::string root_text = root.path().string();
  // A hard link of one recording's file under another recording's name.
  fs::remove(recording(1, 2));
  fs::create_hard_link(recording(1, 1), recording(1, 2));
  EXPECT_MENTIONS(load_error("haptex", root.path()),
                  "manifest.csv:8: file " + recording(1, 2).string() + " already listed on line 7 (recording "
                  "'fabric01_rec1', as " + recording(1, 1).string() + ", a link to the same file)");
  // A byte-identical copy.
  fs::remove(recording(1, 2));
  fs::copy_file(recording(1, 1), recording(1, 2));
  EXPECT_MENTIONS(load_error("haptex", root.path()),
                  recording(1, 2).string() + ": recording 'fabric01_rec2' has the same samples as recording "
                  "'fabric01_rec1' (" + recording(1, 1).string() + ")");
  // Paths out of the dataset folder, relative or absolute.
  replace_in(manifest(), "recordings/fabric01_2.csv,", "../other/fabric01_2.csv,");
  EXPECT_MENTIONS(load_error("haptex", root.path()),
                  "manifest.csv:8: file '../other/fabric01_2.csv' is outside the dataset folder");
  replace_in(manifest(), "../other/fabric01_2.csv,", "recordings/../../x.csv,");
  EXPECT_MENTIONS(load_error("haptex", root.path()), "file 'recordings/../../x.csv' is outside the dataset folder");
  replace_in(manifest(), "recordings/../../x.csv,", recording(1, 2).string() + ",");
  EXPECT_MENTIONS(load_error("haptex", root.path()), "is outside the dataset folder; expected a path relative to");
}

TEST_F(HaptexManifestErrors, DuplicateRecordingIds) {
  replace_in(manifest(), "fabric01_rec2\n", "fabric01_rec1\n");
  EXPECT_MENTIONS(load_error("haptex", root.path()),
                  "manifest.csv:8: recording 'fabric01_rec1' already listed on line 7");
}

TEST_F(HaptexManifestErrors, MissingChannelColumnInARecording) {
  replace_in(recording(1, 0), "velocity", "speed");
  EXPECT_MENTIONS(load_error("haptex", root.path()), "fabric01_0.csv: no column 'velocity'");
}

TEST_F(HaptexManifestErrors, RecordingRowWithAWrongColumnCount) {
  replace_in(recording(3, 3), "velocity\n", "velocity\n0,1\n");
  EXPECT_MENTIONS(load_error("haptex", root.path()), "fabric03_3.csv:2: 2 fields, expected 5");
}

TEST_F(HaptexManifestErrors, NonNumericAndNanValuesNameLineAndColumn) {
  replace_in(recording(0, 0), ",0.05000\n", ",fast\n");
  EXPECT_MENTIONS(load_error("haptex", root.path()), "fabric00_0.csv:2 column velocity: 'fast' is not a number");
  replace_in(recording(0, 0), "fast", "NaN");
  EXPECT_MENTIONS(load_error("haptex", root.path()), "fabric00_0.csv:2 column velocity: NaN found");
}

TEST_F(HaptexManifestErrors, ARecordingPastTheTextSizeLimitIsRefusedBeforeItIsRead) {
  // A sparse file: 1 GiB and one byte of text on a disk that keeps none of it.
  fs::resize_file(recording(2, 1), kMaxTextFileBytes + 1);
  EXPECT_MENTIONS(load_error("haptex", root.path()), "fabric02_1.csv: 1073741825 bytes, expected a text file of at most 1073741824 bytes");
}

TEST_F(HaptexManifestErrors, UnknownSplitAndMalformedContext) {
  write_text(manifest(), "file,class,group,recording,split\nrecordings/fabric00_0.csv,a,g,r0,holdout\n");
  EXPECT_MENTIONS(load_error("haptex", root.path()), "manifest.csv:2: split 'holdout', expected train, validation");
  write_text(manifest(), "file,class,group,recording,context\nrecordings/fabric00_0.csv,a,g,r0,speed\n");
  EXPECT_MENTIONS(load_error("haptex", root.path()), "manifest.csv:2: context 'speed', expected key=number pairs");
  // A repeat is not a default (the last would win), and held_out is a flag, not a weight.
  write_text(manifest(), "file,class,group,recording,context\nrecordings/fabric00_0.csv,a,g,r0,speed=1;speed=2\n");
  EXPECT_MENTIONS(load_error("haptex", root.path()),
                  "manifest.csv:2: context 'speed=1;speed=2' gives 'speed' twice, expected each key once");
  write_text(manifest(), "file,class,group,recording,context\nrecordings/fabric00_0.csv,a,g,r0,held_out=2\n");
  EXPECT_MENTIONS(load_error("haptex", root.path()), "manifest.csv:2: context held_out=2, expected 1 (held out) or 0");
}

TEST_F(HaptexManifestErrors, SpreadsheetLineEndsAndByteOrderMarksAreReadAndInvisibleBytesAreShown) {
  // A manifest and a recording saved by a spreadsheet (byte-order mark, CRLF) read as the originals.
  for (const fs::path& file : {manifest(), recording(1, 0)}) {
    std::string text = read_text(file);
    for (auto at = text.find('\n'); at != std::string::npos; at = text.find('\n', at + 2)) text.insert(at, "\r");
    write_text(file, "\xEF\xBB\xBF" + text);
  }
  EXPECT_EQ(load_error("haptex", root.path()), "");
  // A column that differs only by invisible bytes is shown with them spelled out, and a huge
  // field is cut.
  replace_in(recording(1, 0), "velocity", "velocity\x01");
  EXPECT_MENTIONS(load_error("haptex", root.path()), "fabric01_0.csv: no column 'velocity' in the header");
  EXPECT_MENTIONS(load_error("haptex", root.path()), ",velocity\\x01)");
  write_text(manifest(), "file,class,group,recording,split\nrecordings/fabric00_0.csv,a,g,r0,\xEF\xBB\xBFtest\x1b[31m" +
                             std::string(500'000, 'x') + "\n");
  const std::string message = load_error("haptex", root.path());
  EXPECT_MENTIONS(message, "manifest.csv:2: split '\\ufefftest\\x1b[31mxxx");
  EXPECT_MENTIONS(message, "... (500012 bytes in all)', expected train, validation");
  EXPECT_LT(message.size(), 400u);
  // A file without line breaks is no table: refused at its first MiB, not read whole as one line.
  write_text(manifest(), "file,class,group,recording,split\n" + std::string(3'000'000, 'x'));
  EXPECT_MENTIONS(load_error("haptex", root.path()), "manifest.csv:2: a line longer than 1 MiB, expected the rows");
}

class AudioErrors : public ::testing::Test {
 protected:
  AudioErrors() { write_ls100_fixture(root.path(), {}); }
  fs::path clip(int c, int index) const { return root.path() / fmt::format("{}/{}-{:04d}.wav", 100 + c, 100 + c, index); }
  TemporaryDirectory root;
};

TEST_F(AudioErrors, TruncatedWav) {
  write_wav(clip(1, 9), std::vector<float>(1000, 0.1f), 16000, 32000);
  EXPECT_MENTIONS(load_error("ls100", root.path()), "101-0009.wav: truncated");
}

TEST_F(AudioErrors, EmptyWav) {
  write_wav(clip(0, 2), {}, 16000);
  EXPECT_MENTIONS(load_error("ls100", root.path()), "100-0002.wav: no audio samples");
}

TEST_F(AudioErrors, NotAWav) {
  write_text(clip(0, 2), "hello");
  EXPECT_MENTIONS(load_error("ls100", root.path()), "100-0002.wav: not a readable audio file");
}

TEST_F(AudioErrors, ShortClip) {
  write_wav(clip(2, 16), std::vector<float>(16000, 0.1f), 16000);
  EXPECT_MENTIONS(load_error("ls100", root.path()), "102-0016.wav: 16000 samples, shorter than one segment of 32000");
}

TEST_F(AudioErrors, WrongSampleRateIsAnErrorNotAResample) {
  write_wav(clip(3, 24), std::vector<float>(44100 * 2, 0.1f), 44100);
  EXPECT_MENTIONS(load_error("ls100", root.path()), "103-0024.wav: sample rate 44100 Hz, expected 16000 Hz");
}

TEST_F(AudioErrors, ListedFileMissingAndListedTwice) {
  replace_in(root.path() / "librispeech_fscil_test.csv", "100/100-0006.wav", "100/100-0099.wav");
  EXPECT_MENTIONS(load_error("ls100", root.path()), "librispeech_fscil_test.csv:2: audio file");
  replace_in(root.path() / "librispeech_fscil_test.csv", "100/100-0099.wav", "100/100-0000.wav");
  EXPECT_MENTIONS(load_error("ls100", root.path()),
                  "librispeech_fscil_test.csv:2: 100/100-0000.wav is already listed at");
}

TEST_F(AudioErrors, AFileNameNoFileSystemTakesIsUnreadable) {
  replace_in(root.path() / "librispeech_fscil_test.csv", "100/100-0006.wav", "100/" + std::string(300, 'x') + ".wav");
  EXPECT_MENTIONS(load_error("ls100", root.path()), "librispeech_fscil_test.csv:2: audio file");
  EXPECT_MENTIONS(load_error("ls100", root.path()), "xxx.wav: unreadable (File name too long)");
}

// The readers themselves, reached without an adapter's check first: a name no file system takes is
// a file that is not there, not a filesystem_error.
TEST(FileReaders, ANameNoFileSystemTakesIsNoSuchFile) {
  TemporaryDirectory directory;
  const fs::path too_long = directory.path() / (std::string(300, 'x') + ".csv");
  const auto message_of = [](const auto& read) {
    try {
      read();
    } catch (const DatasetError& error) {
      return std::string(error.what());
    }
    return std::string("no DatasetError");
  };
  EXPECT_MENTIONS(message_of([&] { read_text_table(too_long); }), "xxx.csv: unreadable (File name too long)");
  EXPECT_MENTIONS(message_of([&] { read_mono_audio(too_long, 16000); }),
                  "xxx.csv: unreadable (File name too long), expected an audio file");
}

TEST_F(AudioErrors, MissingListAndBadLabel) {
  replace_in(root.path() / "librispeech_fscil_val.csv", ",100,0\n", ",100,zero\n");
  EXPECT_MENTIONS(load_error("ls100", root.path()), "librispeech_fscil_val.csv:2: label 'zero'");
  fs::remove(root.path() / "librispeech_fscil_val.csv");
  EXPECT_MENTIONS(load_error("ls100", root.path()), "librispeech_fscil_val.csv: no such file");
}

TEST(Ns100Errors, InstrumentMissingFromTheVocabulary) {
  TemporaryDirectory root;
  write_ns100_fixture(root.path(), {2, 1, 1, 1});
  replace_in(root.path() / "nsynth-100-fs-meta/nsynth-100-fs_vocab.json", "\"instrument_1\"", "\"organ_1\"");
  EXPECT_MENTIONS(load_error("ns100", root.path()), "nsynth-100-fs_train.csv:3: instrument 'instrument_1' is not in");
}

TEST(RealDatasetCache, AFailedLoadLeavesTheCachedFilesUntouched) {
  TemporaryDirectory root, cache;
  write_haptex_fixture(root.path(), {});
  ASSERT_EQ(load_error("haptex", root.path(), {}, cache.path()), "");
  std::map<fs::path, std::string> before;
  for (const auto& entry : fs::directory_iterator(cache.path())) before[entry.path()] = read_text(entry.path());
  ASSERT_EQ(before.size(), 1u);

  replace_in(root.path() / "recordings/fabric03_3.csv", ",0.05000\n", ",inf\n");
  EXPECT_MENTIONS(load_error("haptex", root.path(), {}, cache.path()), "fabric03_3.csv:2 column velocity: inf found");
  std::map<fs::path, std::string> after;
  for (const auto& entry : fs::directory_iterator(cache.path())) after[entry.path()] = read_text(entry.path());
  EXPECT_EQ(after, before);
}

TEST(RealDatasetCache, UnchangedFilesAreServedFromTheCacheAndAChangedFileIsNot) {
  TemporaryDirectory root, cache;
  write_haptex_fixture(root.path(), {});
  ASSERT_EQ(load_error("haptex", root.path(), {}, cache.path()), "");
  ASSERT_EQ(load_error("haptex", root.path(), {}, cache.path()), "");
  EXPECT_EQ(std::distance(fs::directory_iterator(cache.path()), fs::directory_iterator()), 1);
  replace_in(root.path() / "recordings/fabric00_0.csv", ",0.05000\n", ",0.060001\n");
  ASSERT_EQ(load_error("haptex", root.path(), {}, cache.path()), "");
  EXPECT_EQ(std::distance(fs::directory_iterator(cache.path()), fs::directory_iterator()), 2);
}

}  // namespace
}  // namespace fscil
