#include "datasets/readers/folder_adapter.h"

#include <fmt/format.h>
#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/error.h"
#include "core/json_keys.h"
#include "core/text_file.h"
#include "datasets/readers/regular_file.h"
#include "datasets/readers/text_table.h"
#include "core/shown_text.h"
#include "core/valid_range.h"

namespace fscil {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// What a named dataset in the folder format must declare; absent fields take these values.
struct FolderExpectation {
  std::string name;
  double sample_rate;
  std::vector<std::string> channels;
  double segment_seconds;
  std::string preset;
  SessionDefaults sessions;
};

// Reads dataset.json fields with errors naming the file, the field and the expected type.
class DatasetJson {
 public:
  explicit DatasetJson(const fs::path& path) : path_(path) {
    if (!names_a_regular_file(path)) {
      throw DatasetError(fmt::format("{}: {}, expected the folder format's dataset.json", path.string(),
                                     why_not_a_regular_file(path)));
    }
    const std::string text = read_text_file(path);
    try {
      root_ = json::parse(text);
    } catch (const json::exception& error) {
      throw DatasetError(fmt::format("{}: not valid JSON ({})", path.string(), error.what()));
    }
    if (const auto key = duplicated_json_key(text)) {
      throw DatasetError(fmt::format("{}: field '{}' given twice in one object; give it once", path.string(),
                                     shown_text(*key)));
    }
    if (!root_.is_object()) throw DatasetError(fmt::format("{}: expected a JSON object", path.string()));
  }

  const json& root() const { return root_; }

  double number(const json& object, const std::string& field, const ValidRange& valid,
                std::optional<double> fallback = {}) const {
    if (!object.contains(field)) return required(field, fallback, "a number");
    if (!object[field].is_number() || !valid.contains(object[field].get<double>())) {
      fail(field, "a number " + valid.describe());
    }
    return object[field].get<double>();
  }
  std::int64_t integer(const json& object, const std::string& field, const ValidRange& valid,
                       std::int64_t fallback) const {
    if (!object.contains(field)) return fallback;
    if (!object[field].is_number_integer() || !valid.contains(object[field].get<double>())) {
      fail(field, "an integer " + valid.describe());
    }
    return object[field].get<std::int64_t>();
  }
  std::string text(const json& object, const std::string& field, std::optional<std::string> fallback = {}) const {
    if (!object.contains(field)) return required(field, fallback, "a string");
    if (!object[field].is_string()) fail(field, "a string");
    return object[field].get<std::string>();
  }
  bool boolean(const json& object, const std::string& field, bool fallback) const {
    if (!object.contains(field)) return fallback;
    if (!object[field].is_boolean()) fail(field, "true or false");
    return object[field].get<bool>();
  }
  std::vector<std::string> names(const json& object, const std::string& field,
                                 std::optional<std::vector<std::string>> fallback = {}) const {
    if (!object.contains(field)) return required(field, fallback, "a list of names");
    const json& list = object[field];
    if (!list.is_array() || list.empty()) fail(field, "a non-empty list of names");
    std::vector<std::string> result;
    for (const auto& item : list) {
      if (!item.is_string() || item.get<std::string>().empty()) fail(field, "a list of names");
      if (std::find(result.begin(), result.end(), item.get<std::string>()) != result.end()) {
        fail(field, fmt::format("a list of distinct names ('{}' is listed twice)", shown_text(item.get<std::string>())));
      }
      result.push_back(item.get<std::string>());
    }
    return result;
  }
  const json& object(const std::string& field) const {
    static const json empty = json::object();
    if (!root_.contains(field)) return empty;
    if (!root_[field].is_object()) fail(field, "an object");
    return root_[field];
  }
  // A misspelt field would silently take its default: every key of `object` must be one of `known`.
  void require_known_keys(const json& object, const std::string& where, const std::vector<std::string>& known) const {
    for (const auto& [key, value] : object.items()) {
      if (std::find(known.begin(), known.end(), key) == known.end()) {
        throw DatasetError(fmt::format("{}: unknown field '{}{}', expected one of {}", path_.string(), where,
                                       shown_text(key), fmt::join(known, ", ")));
      }
    }
  }
  [[noreturn]] void fail(const std::string& field, const std::string& expected) const {
    throw DatasetError(fmt::format("{}: field '{}': expected {}", path_.string(), field, expected));
  }

 private:
  template <typename T>
  T required(const std::string& field, const std::optional<T>& fallback, const std::string& expected) const {
    if (!fallback) throw DatasetError(fmt::format("{}: field '{}' missing, expected {}", path_.string(), field, expected));
    return *fallback;
  }

  fs::path path_;
  json root_;
};

template <typename T>
void require_value(const fs::path& path, const std::string& field, const T& got, const T& expected,
                   const std::string& dataset) {
  if (got != expected) {
    throw DatasetError(fmt::format("{}: field '{}' is {}, {} expects {}", path.string(), field, fmt::format("{}", got),
                                   dataset, fmt::format("{}", expected)));
  }
}

LogMelSettings front_end_of(const DatasetJson& config, double sample_rate, const std::string& default_preset) {
  const json& spec = config.object("front_end");
  const std::string preset = config.text(spec, "preset", default_preset);
  LogMelSettings settings;
  if (!preset.empty()) {
    settings = log_mel_preset(preset);
  } else {  // the paper's tactile settings
    settings.n_fft = 128;
    settings.hop = 16;
    settings.n_mels = 64;
    settings.center = false;
  }
  settings.sample_rate = sample_rate;
  settings.n_fft = config.integer(spec, "n_fft", ValidRange::at_least(2), settings.n_fft);
  settings.hop = config.integer(spec, "hop", ValidRange::at_least(1), settings.hop);
  settings.n_mels = config.integer(spec, "n_mels", ValidRange::at_least(1), settings.n_mels);
  settings.f_min = config.number(spec, "f_min", ValidRange::at_least(0), settings.f_min);
  settings.f_max = config.number(spec, "f_max", ValidRange::at_least(0), settings.f_max);
  settings.center = config.boolean(spec, "center", settings.center);
  return settings;
}

// Protocol defaults when dataset.json gives none: 5-way 5-shot, about 60% of classes in the base session.
SessionDefaults sessions_of(const DatasetJson& config, int classes, const SessionDefaults& fallback) {
  const json& spec = config.object("sessions");
  SessionDefaults defaults = fallback;
  if (defaults.sessions == 0) {
    const int incremental = std::max(1, classes * 2 / 5 / 5);
    const int way = std::min(5, (classes - 1) / incremental);  // fewer than 5 new classes a session in small sets
    defaults = {classes - way * incremental, way, 5, 1 + incremental};
  }
  const auto count = [&](const char* field, int fallback, const ValidRange& valid) {
    return static_cast<int>(config.integer(spec, field, valid, fallback));
  };
  defaults.base_classes = count("base_classes", defaults.base_classes, ValidRange::between(1, classes));
  defaults.way = count("way", defaults.way, ValidRange::between(1, classes));
  defaults.shot = count("shot", defaults.shot, ValidRange::at_least(1));
  defaults.sessions = count("sessions", defaults.sessions, ValidRange::between(1, classes));
  // Classes no session takes would be in the data and in no result: say so rather than drop them.
  const std::int64_t used = defaults.base_classes + static_cast<std::int64_t>(defaults.way) * (defaults.sessions - 1);
  if (spec.contains("sessions") && used != classes) {
    config.fail("sessions", fmt::format("a protocol over the {} classes of the manifest: base_classes {} + way {} x "
                                        "(sessions {} - 1) takes {}", classes, defaults.base_classes, defaults.way,
                                        defaults.sessions, used));
  }
  return defaults;
}

SplitHint parse_split(const std::string& text, const std::string& where) {
  if (text.empty()) return SplitHint::none;
  if (text == "train") return SplitHint::train;
  if (text == "validation" || text == "val") return SplitHint::validation;
  if (text == "test") return SplitHint::test;
  throw DatasetError(fmt::format("{}: split '{}', expected train, validation, test or empty", where, shown_text(text)));
}

// "speed=1.2;device=3" -> {speed: 1.2, device: 3}
std::map<std::string, double> parse_context(const std::string& text, const std::string& where) {
  std::map<std::string, double> context;
  std::stringstream items(text);
  std::string item;
  while (std::getline(items, item, ';')) {
    if (item.empty()) continue;
    const auto equals = item.find('=');
    if (equals == std::string::npos || equals == 0) {
      throw DatasetError(fmt::format("{}: context '{}', expected key=number pairs separated by ';'", where, shown_text(item)));
    }
    context[item.substr(0, equals)] = parse_finite_float(item.substr(equals + 1), where + " context " + shown_text(item));
  }
  return context;
}

std::vector<fs::path> files_of(const std::string& field, const fs::path& root, std::size_t channels,
                               const std::string& where) {
  std::vector<fs::path> files;
  std::stringstream items(field);
  std::string item;
  while (std::getline(items, item, ';')) {
    const fs::path relative = fs::path(item).lexically_normal();
    if (relative.is_absolute() || (!relative.empty() && *relative.begin() == "..")) {
      throw DatasetError(fmt::format("{}: file '{}' is outside the dataset folder; expected a path relative to {} and "
                                     "inside it", where, shown_text(item), root.string()));
    }
    const fs::path file = root / item;
    if (!names_a_regular_file(file)) {
      throw DatasetError(fmt::format("{}: file {}: {}", where, shown_text(file.string()), why_not_a_regular_file(file)));
    }
    files.push_back(file);
  }
  if (files.empty()) throw DatasetError(fmt::format("{}: empty file field", where));
  const bool one_csv = files.size() == 1 && files[0].extension() == ".csv";
  const bool txt_per_channel = files.size() == channels &&
                               std::all_of(files.begin(), files.end(), [](const fs::path& f) { return f.extension() == ".txt"; });
  if (!one_csv && !txt_per_channel) {
    throw DatasetError(fmt::format("{}: '{}', expected one .csv file or {} .txt files (one per channel) separated by ';'",
                                   where, shown_text(field), channels));
  }
  return files;
}

// A file as the file system knows it: two names (a hard link, a symbolic link) are one file.
using FileIdentity = std::pair<dev_t, ino_t>;

FileIdentity identity_of(const fs::path& file) {
  struct stat status {};
  if (::stat(file.c_str(), &status) != 0) throw DatasetError(fmt::format("{}: cannot be read", file.string()));
  return {status.st_dev, status.st_ino};
}

// Where the manifest listed a file.
struct ListedFile {
  fs::path path;
  int line;
  std::string recording;
};

SignalData read_folder_recording(const RecordingSource& source, const std::vector<std::string>& channels) {
  if (source.files.front().extension() == ".csv") return read_signal_csv(source.files.front(), channels);
  return stack_channel_files(source.files, read_single_column);
}

DatasetScan scan_folder(const fs::path& root, const FolderExpectation* expected) {
  const fs::path config_path = root / "dataset.json";
  const DatasetJson config(fenced_by_root(root, config_path));
  const json& top = config.root();
  config.require_known_keys(top, "", {"name", "sample_rate", "channels", "segment_seconds", "hop_seconds",
                                      "max_segments_per_recording", "front_end", "sessions"});
  config.require_known_keys(config.object("front_end"), "front_end.",
                            {"preset", "n_fft", "hop", "n_mels", "f_min", "f_max", "center"});
  config.require_known_keys(config.object("sessions"), "sessions.", {"base_classes", "way", "shot", "sessions"});

  DatasetScan scan;
  scan.root = root;
  DatasetDescription& d = scan.description;
  d.name = config.text(top, "name", expected ? std::optional(expected->name) : std::nullopt);
  if (d.name.empty() || d.name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_.-") !=
                            std::string::npos) {
    config.fail("name", "letters, digits, '_', '.' or '-' (it names cache and result files)");
  }
  d.sample_rate = config.number(top, "sample_rate", ValidRange::above(0),
                                expected ? std::optional(expected->sample_rate) : std::nullopt);
  d.channel_names = config.names(top, "channels", expected ? std::optional(expected->channels) : std::nullopt);
  const double segment_seconds =
      config.number(top, "segment_seconds", ValidRange::above(0),
                    expected ? std::optional(expected->segment_seconds) : std::nullopt);
  const double hop_seconds = config.number(top, "hop_seconds", ValidRange::above(0), segment_seconds);
  if (expected != nullptr) {
    require_value(config_path, "sample_rate", d.sample_rate, expected->sample_rate, expected->name);
    require_value(config_path, "channels", fmt::format("{}", fmt::join(d.channel_names, ",")),
                  fmt::format("{}", fmt::join(expected->channels, ",")), expected->name);
    require_value(config_path, "segment_seconds", segment_seconds, expected->segment_seconds, expected->name);
  }
  const auto segment = static_cast<std::int64_t>(std::lround(segment_seconds * d.sample_rate));
  const auto hop = static_cast<std::int64_t>(std::lround(hop_seconds * d.sample_rate));
  if (segment < 1 || hop < 1) config.fail("segment_seconds", "segment and hop of at least one sample");
  d.segment = {segment, hop, config.integer(top, "max_segments_per_recording", ValidRange::at_least(0), 0)};
  d.front_end = front_end_of(config, d.sample_rate, expected ? expected->preset : "");

  const fs::path manifest_path = root / "manifest.csv";
  const TextTable manifest = read_text_table(fenced_by_root(root, manifest_path));
  const std::size_t file_column = manifest.column("file"), class_column = manifest.column("class"),
                    group_column = manifest.column("group"), recording_column = manifest.column("recording");
  const bool has_split = manifest.has_column("split"), has_context = manifest.has_column("context");
  std::map<std::string, int> class_of, group_of, line_of_recording;
  std::map<FileIdentity, ListedFile> listing_of_file;
  for (std::size_t r = 0; r < manifest.rows.size(); ++r) {
    const auto& row = manifest.rows[r];
    const std::string where = fmt::format("{}:{}", manifest_path.string(), manifest.line_of_row[r]);
    RecordingSource source;
    source.id = row[recording_column];
    if (source.id.empty() || row[class_column].empty() || row[group_column].empty()) {
      throw DatasetError(fmt::format("{}: empty recording, class or group, expected a name in each", where));
    }
    const auto [previous, fresh] = line_of_recording.emplace(source.id, manifest.line_of_row[r]);
    if (!fresh) {
      throw DatasetError(fmt::format("{}: recording '{}' already listed on line {}; recording ids must be unique",
                                     where, shown_text(source.id), previous->second));
    }
    source.class_index = class_of.emplace(row[class_column], static_cast<int>(class_of.size())).first->second;
    if (source.class_index == static_cast<int>(d.class_names.size())) d.class_names.push_back(row[class_column]);
    source.group_index = group_of.emplace(row[group_column], static_cast<int>(group_of.size())).first->second;
    if (source.group_index == static_cast<int>(d.group_names.size())) d.group_names.push_back(row[group_column]);
    if (has_split) source.split = parse_split(row[manifest.column("split")], where);
    if (has_context) source.context = parse_context(row[manifest.column("context")], where);
    source.files = files_of(row[file_column], root, d.channel_names.size(), where);
    // A file under two recordings (or classes, or splits) would put the same signal on both sides
    // of a split: under two names, a symbolic link or a hard link it is still one file.
    for (const auto& file : source.files) {
      const auto [listed, first] = listing_of_file.emplace(identity_of(file), ListedFile{file, manifest.line_of_row[r], source.id});
      if (!first) {
        throw DatasetError(fmt::format("{}: file {} already listed on line {} (recording '{}'{}); a file belongs to one "
                                       "recording", where, file.string(), listed->second.line, listed->second.recording,
                                       fs::weakly_canonical(file) == fs::weakly_canonical(listed->second.path)
                                           ? ""
                                           : ", as " + listed->second.path.string() + ", a link to the same file"));
      }
    }
    scan.recordings.push_back(std::move(source));
  }
  if (scan.recordings.empty()) {
    throw DatasetError(fmt::format("{}: no recordings, expected a row per recording", manifest_path.string()));
  }
  if (d.class_names.size() < 2) {
    throw DatasetError(fmt::format("{}: 1 class, expected at least 2 (a class-incremental protocol needs base classes "
                                   "and new ones)", manifest_path.string()));
  }
  d.sessions = sessions_of(config, static_cast<int>(d.class_names.size()),
                           expected ? expected->sessions : SessionDefaults{0, 5, 5, 0});
  d.source = expected ? expected->name : "folder";
  scan.read = [channels = d.channel_names](const RecordingSource& source) {
    return read_folder_recording(source, channels);
  };
  scan.refuse_identical_recordings = true;
  return scan;
}

}  // namespace

std::vector<std::string> haptex_channel_names() {
  return {"friction_force", "normal_force", "friction_coefficient", "displacement", "velocity"};
}

DatasetScan scan_tactile_folder(const fs::path& root) { return scan_folder(root, nullptr); }

DatasetScan scan_haptex(const fs::path& root) {
  const FolderExpectation haptex{"haptex", 1000, haptex_channel_names(), 0.5, "haptex", {75, 5, 5, 10}};
  DatasetScan scan = scan_folder(root, &haptex);
  scan.description.name = "haptex";
  return scan;
}

}  // namespace fscil
