#include "datasets/readers/lmt108_adapter.h"

#include <fmt/format.h>

#include <map>
#include <regex>
#include <tuple>

#include "core/error.h"
#include "datasets/readers/text_table.h"
#include "datasets/readers/wav_file.h"
#include "core/parameter_set.h"
#include "core/number_text.h"

namespace fscil {

namespace fs = std::filesystem;

namespace {

constexpr double kSampleRate = 10000;
const char* const kAxes[] = {"X", "Y", "Z"};

// A recording is named by its material, the database's side (train or test) and its number.
using RecordingKey = std::tuple<std::string, std::string, int>;

struct ExtraChannel {
  std::string name;
  fs::path folder;
  std::regex pattern;  // captures material, side, number
};

// A recording's number in its file name: digits the name pattern matched, refused when too many.
int recording_number(const std::string& digits, const fs::path& file) {
  const auto number = parse_number<int>(digits);
  if (!number) throw DatasetError(fmt::format("{}: recording number {} is too large", file.string(), digits));
  return *number;
}

// Files of one kind under `folder` (any depth), by recording.
std::map<RecordingKey, fs::path> index_files(const fs::path& folder, const std::regex& pattern) {
  if (!fs::is_directory(folder)) {
    throw DatasetError(fmt::format("{}: no such folder (asked for by lmt108_signals)", folder.string()));
  }
  std::map<RecordingKey, fs::path> files;
  for (const auto& entry : fs::recursive_directory_iterator(folder)) {
    std::smatch match;
    const std::string name = entry.path().filename().string();
    if (entry.is_regular_file() && std::regex_match(name, match, pattern)) {
      files[{match[1], match[2], recording_number(match[3], entry.path())}] = entry.path();
    }
  }
  return files;
}

// LMT108 names each material after its group: G1EpoxyRasterPlate is in G1.
std::string group_of_material(const std::string& material, const fs::path& file) {
  std::smatch match;
  static const std::regex group_prefix(R"(^(G\d+)[A-Za-z].*)");
  if (!std::regex_match(material, match, group_prefix)) {
    throw DatasetError(fmt::format("{}: material '{}' does not start with its group G1..G9", file.string(), material));
  }
  return match[1];
}

SignalData read_lmt_recording(const RecordingSource& source) {
  return stack_channel_files(source.files, [](const fs::path& file) {
    if (file.extension() != ".wav") return read_single_column(file);
    std::vector<float> samples = read_mono_audio(file, kSampleRate);
    const auto length = static_cast<std::int64_t>(samples.size());
    return SignalData{1, length, std::move(samples)};
  });
}

}  // namespace

DatasetScan scan_lmt108(const fs::path& root, const ParameterSet& params) {
  const std::string signals = params.choice("lmt108_signals", "accel",
                                            {"accel", "accel+friction", "accel+sound", "accel+friction+sound"});
  const fs::path movement = root / "AccelScansComponents" / "Movement";
  const std::map<std::string, std::string> sides = {{"Training", "train"}, {"Testing", "test"}};

  // material -> side/number -> axis files
  std::map<RecordingKey, std::map<std::string, fs::path>> axes;
  const std::regex accel_name(R"(^([^_]+)_Movement_([XYZ])_(train|test)(\d+)\.txt$)");
  for (const auto& [folder, side] : sides) {
    const fs::path directory = movement / folder;
    if (!fs::is_directory(directory)) {
      throw DatasetError(fmt::format("{}: no such folder, expected the LMT108 layout "
                                     "AccelScansComponents/Movement/{{Training,Testing}}/"
                                     "<Material>_Movement_{{X,Y,Z}}_{{train,test}}<n>.txt", directory.string()));
    }
    for (const auto& entry : fs::directory_iterator(directory)) {
      std::smatch match;
      const std::string name = entry.path().filename().string();
      if (!entry.is_regular_file() || !std::regex_match(name, match, accel_name)) continue;
      if (match[3] != side) {
        throw DatasetError(fmt::format("{}: a {} recording in the {} folder", entry.path().string(), match[3].str(),
                                       folder));
      }
      group_of_material(match[1], entry.path());
      axes[{match[1], side, recording_number(match[4], entry.path())}][match[2]] = entry.path();
    }
  }
  if (axes.empty()) {
    throw DatasetError(fmt::format("{}: no <Material>_Movement_X_train<n>.txt files, expected the LMT108 layout",
                                   movement.string()));
  }

  std::vector<ExtraChannel> extras;
  if (signals.find("friction") != std::string::npos) {
    extras.push_back({"friction", root / "FricScans", std::regex(R"(^([^_]+)_FrictionFSR1_Movement_(train|test)(\d+)\.txt$)")});
  }
  if (signals.find("sound") != std::string::npos) {
    extras.push_back({"sound", root / "SoundScans", std::regex(R"(^([^_]+)_.*_(train|test)(\d+)\.wav$)")});
  }
  std::vector<std::map<RecordingKey, fs::path>> extra_files;
  for (const auto& extra : extras) extra_files.push_back(index_files(extra.folder, extra.pattern));

  DatasetScan scan;
  scan.root = root;
  DatasetDescription& d = scan.description;
  d.name = "lmt108";
  d.sample_rate = kSampleRate;
  d.channel_names = {"accel_x", "accel_y", "accel_z"};
  for (const auto& extra : extras) d.channel_names.push_back(extra.name);
  std::map<std::string, int> class_of, group_of;
  for (const auto& [key, files] : axes) class_of.emplace(std::get<0>(key), 0);
  for (auto& [material, index] : class_of) {
    index = static_cast<int>(d.class_names.size());
    d.class_names.push_back(material);
    group_of.emplace(group_of_material(material, movement), 0);
  }
  for (auto& [group, index] : group_of) {
    index = static_cast<int>(d.group_names.size());
    d.group_names.push_back(group);
  }

  for (const auto& [key, files] : axes) {
    const auto& [material, side, number] = key;
    RecordingSource source;
    source.id = fmt::format("{}_{}{}", material, side, number);
    source.class_index = class_of.at(material);
    source.group_index = group_of.at(group_of_material(material, movement));
    source.split = side == "test" ? SplitHint::test : SplitHint::train;
    for (const char* axis : kAxes) {
      const auto found = files.find(axis);
      if (found == files.end()) {
        const fs::path missing = movement / (side == "test" ? "Testing" : "Training") /
                                 fmt::format("{}_Movement_{}_{}{}.txt", material, axis, side, number);
        throw DatasetError(fmt::format("{}: no such file (recording {} needs X, Y and Z)", missing.string(), source.id));
      }
      source.files.push_back(found->second);
    }
    for (std::size_t e = 0; e < extras.size(); ++e) {
      const auto found = extra_files[e].find(key);
      if (found == extra_files[e].end()) {
        throw DatasetError(fmt::format("{}: no {} file for recording {} (lmt108_signals={})", extras[e].folder.string(),
                                       extras[e].name, source.id, signals));
      }
      source.files.push_back(found->second);
    }
    scan.recordings.push_back(std::move(source));
  }
  const auto segment = static_cast<std::int64_t>(0.8 * kSampleRate);
  d.segment = {segment, segment, 0};
  d.front_end = log_mel_preset("lmt108");
  d.sessions = {63, 5, 5, 10};
  d.source = fmt::format("lmt108 signals={}", signals);
  scan.read = read_lmt_recording;
  return scan;
}

}  // namespace fscil
