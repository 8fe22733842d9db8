#include "datasets/readers/audio_adapters.h"

#include <fmt/format.h>

#include <fstream>
#include <map>
#include <iterator>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/json_fields.h"
#include "datasets/readers/regular_file.h"
#include "datasets/readers/text_table.h"
#include "datasets/readers/wav_file.h"
#include "core/shown_text.h"
#include "core/number_text.h"

namespace fscil {

namespace fs = std::filesystem;

namespace {

constexpr double kAudioRate = 16000;
// PITS-SC feeds a mono clip to the 3-channel ResNet by repeating it; we store it once.
constexpr int kAudioChannelRepeat = 3;

struct ListedSplit {
  const char* suffix;
  SplitHint hint;
};
const ListedSplit kListedSplits[] = {{"train", SplitHint::train}, {"val", SplitHint::validation},
                                     {"test", SplitHint::test}};

int parse_label(const std::string& field, const std::string& where) {
  const auto label = parse_number<int>(field);
  if (!label || *label < 0) {
    throw DatasetError(fmt::format("{}: label '{}', expected a class index >= 0", where, shown_text(field)));
  }
  return *label;
}

// One clip per row; the clip's file is its recording id, so a file listed twice is an error.
class ClipCollector {
 public:
  explicit ClipCollector(DatasetScan& scan) : scan_(scan) {}

  void add(const fs::path& file, int class_index, SplitHint split, const std::string& where) {
    if (!names_a_regular_file(file)) {
      throw DatasetError(fmt::format("{}: audio file {}: {}", where, file.string(), why_not_a_regular_file(file)));
    }
    const std::string id = fs::relative(file, scan_.root).string();
    const auto [previous, fresh] = where_of_.emplace(id, where);
    if (!fresh) throw DatasetError(fmt::format("{}: {} is already listed at {}", where, id, previous->second));
    RecordingSource source;
    source.id = id;
    source.class_index = class_index;
    source.split = split;
    source.files = {file};
    scan_.recordings.push_back(std::move(source));
  }

 private:
  DatasetScan& scan_;
  std::map<std::string, std::string> where_of_;
};

void describe_audio(DatasetScan& scan, const std::string& name, double seconds, SessionDefaults sessions) {
  DatasetDescription& d = scan.description;
  d.name = name;
  d.sample_rate = kAudioRate;
  d.channel_names = {"mono"};
  d.channel_repeat = kAudioChannelRepeat;
  d.group_names = {"all"};
  const auto length = static_cast<std::int64_t>(seconds * kAudioRate);
  d.segment = {length, length, 1};  // one segment per clip, from its start
  d.front_end = log_mel_preset(name);
  d.sessions = sessions;
  d.source = name;
  scan.read = [](const RecordingSource& source) {
    std::vector<float> samples = read_mono_audio(source.files.front(), kAudioRate);
    const auto length = static_cast<std::int64_t>(samples.size());
    return SignalData{1, length, std::move(samples)};
  };
}

void require_every_class(const std::vector<std::string>& class_names, const fs::path& listing) {
  for (std::size_t c = 0; c < class_names.size(); ++c) {
    if (class_names[c].empty()) {
      throw DatasetError(fmt::format("{}: class {} has no clips, expected classes numbered 0..{} without gaps",
                                     listing.string(), c, class_names.size() - 1));
    }
  }
}

}  // namespace

DatasetScan scan_ls100(const fs::path& root) {
  DatasetScan scan;
  scan.root = root;
  describe_audio(scan, "ls100", 2.0, {60, 5, 5, 9});
  ClipCollector clips(scan);
  std::vector<std::string>& names = scan.description.class_names;
  for (const auto& split : kListedSplits) {
    const fs::path listing = root / fmt::format("librispeech_fscil_{}.csv", split.suffix);
    const TextTable table = read_text_table(fenced_by_root(root, listing));
    const std::size_t file = table.column("filename"), speaker = table.column("speaker_id"), label = table.column("label");
    for (std::size_t r = 0; r < table.rows.size(); ++r) {
      const auto& row = table.rows[r];
      const std::string where = fmt::format("{}:{}", table.path.string(), table.line_of_row[r]);
      const int class_index = parse_label(row[label], where);
      if (class_index >= static_cast<int>(names.size())) names.resize(class_index + 1);
      const std::string speaker_name = "speaker" + row[speaker];
      if (names[class_index].empty()) names[class_index] = speaker_name;
      if (names[class_index] != speaker_name) {
        throw DatasetError(fmt::format("{}: label {} is {} here but {} elsewhere", where, class_index, speaker_name,
                                       names[class_index]));
      }
      clips.add(root / row[file], class_index, split.hint, where);
    }
  }
  require_every_class(names, root / "librispeech_fscil_train.csv");
  return scan;
}

DatasetScan scan_ns100(const fs::path& root) {
  DatasetScan scan;
  scan.root = root;
  describe_audio(scan, "ns100", 4.0, {55, 5, 5, 10});
  const fs::path meta = root / "nsynth-100-fs-meta";
  const fs::path vocab_path = meta / "nsynth-100-fs_vocab.json";
  std::ifstream vocab_file(vocab_path);
  if (!vocab_file) throw DatasetError(fmt::format("{}: no such file, expected the instrument -> class map", vocab_path.string()));
  std::map<std::string, int> class_of;
  const std::string vocab{std::istreambuf_iterator<char>(vocab_file), std::istreambuf_iterator<char>()};
  refuse_deep_json<DatasetError>(vocab, vocab_path.string(), "a JSON object of instrument: class index");
  try {
    class_of = nlohmann::json::parse(vocab).get<std::map<std::string, int>>();
  } catch (const nlohmann::json::exception& error) {
    throw DatasetError(fmt::format("{}: expected a JSON object of instrument: class index ({})", vocab_path.string(),
                                   json_error_text(error)));
  }
  std::vector<std::string>& names = scan.description.class_names;
  for (const auto& [instrument, index] : class_of) {
    if (index < 0 || index >= static_cast<int>(class_of.size())) {
      throw DatasetError(fmt::format("{}: {} has class {}, expected 0..{}", vocab_path.string(), instrument, index,
                                     class_of.size() - 1));
    }
    if (index >= static_cast<int>(names.size())) names.resize(index + 1);
    if (!names[index].empty()) {
      throw DatasetError(fmt::format("{}: class {} is given to both {} and {}", vocab_path.string(), index, names[index],
                                     instrument));
    }
    names[index] = instrument;
  }
  require_every_class(names, vocab_path);

  ClipCollector clips(scan);
  for (const auto& split : kListedSplits) {
    const fs::path listing = meta / fmt::format("nsynth-100-fs_{}.csv", split.suffix);
    const TextTable table = read_text_table(fenced_by_root(root, listing));
    const std::size_t file = table.column("filename"), instrument = table.column("instrument"),
                      source = table.column("audio_source");
    for (std::size_t r = 0; r < table.rows.size(); ++r) {
      const auto& row = table.rows[r];
      const std::string where = fmt::format("{}:{}", table.path.string(), table.line_of_row[r]);
      const auto found = class_of.find(row[instrument]);
      if (found == class_of.end()) {
        throw DatasetError(fmt::format("{}: instrument '{}' is not in {}", where, row[instrument], vocab_path.string()));
      }
      clips.add(root / row[source] / "audio" / (row[file] + ".wav"), found->second, split.hint, where);
    }
  }
  return scan;
}

}  // namespace fscil
