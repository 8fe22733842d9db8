#include "datasets/readers/folder_adapter.h"

#include <fmt/format.h>
#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "core/error.h"
#include "core/json_fields.h"
#include "core/text_file.h"
#include "datasets/log_mel_settings.h"
#include "datasets/readers/regular_file.h"
#include "datasets/readers/text_table.h"
#include "core/shown_text.h"
#include "core/valid_range.h"

namespace fscil {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// Bounds before work grows: a segment of 100 M samples (400 MB a channel) is past any front end's
// input (the sample rate's bound is LogMelSettings').
constexpr double kMaxSampleRate = LogMelSettings::kMaxSampleRate;
constexpr double kMaxSegmentSamples = 1e8;
constexpr int kMaxShot = 100000;

// What a named dataset in the folder format must declare; absent fields take these values.
struct FolderExpectation {
  std::string name;
  double sample_rate;
  std::vector<std::string> channels;
  double segment_seconds;
  std::string preset;
  SessionDefaults sessions;
};

using DatasetFields = JsonFields<DatasetError>;

// dataset.json as one object, read as strictly as every JSON file here (core/json_fields.h).
json read_dataset_json(const fs::path& path) {
  if (!names_a_regular_file(path)) {
    throw DatasetError(fmt::format("{}: {}, expected the folder format's dataset.json", path.string(),
                                   why_not_a_regular_file(path)));
  }
  return parse_json_object<DatasetError>(read_text_file(path), path.string());
}

// A field a named dataset may leave to its expectation; required otherwise.
template <typename T, typename Read>
T field_or(const DatasetFields& fields, const std::string& key, const std::optional<T>& expected, Read read) {
  return !fields.has(key) && expected ? *expected : read();
}

template <typename T>
void require_value(const fs::path& path, const std::string& field, const T& got, const T& expected,
                   const std::string& dataset) {
  if (got != expected) {
    throw DatasetError(fmt::format("{}: field '{}' is {}, {} expects {}", path.string(), field, fmt::format("{}", got),
                                   dataset, fmt::format("{}", expected)));
  }
}

LogMelSettings front_end_of(const DatasetFields& spec, double sample_rate, std::int64_t segment,
                            const std::string& default_preset) {
  const std::string preset = spec.text("preset", default_preset);
  const auto presets = log_mel_preset_names();
  if (!preset.empty() && std::find(presets.begin(), presets.end(), preset) == presets.end()) {
    spec.fail("preset", fmt::format("one of {}", fmt::join(presets, ", ")));
  }
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
  settings.n_fft = spec.integer("n_fft", ValidRange::between(2, LogMelSettings::kMaxFftSize), settings.n_fft);
  settings.hop = spec.integer("hop", ValidRange::at_least(1), settings.hop);
  settings.n_mels = spec.integer("n_mels", ValidRange::between(1, LogMelSettings::kMaxMelBins), settings.n_mels);
  settings.f_min = spec.number("f_min", ValidRange::at_least(0), settings.f_min);
  settings.f_max = spec.number("f_max", ValidRange::at_least(0), settings.f_max);
  settings.center = spec.flag("center", settings.center);
  if (settings.f_max > sample_rate / 2) {  // filters past Nyquist are empty: features of nothing
    spec.fail("f_max", fmt::format("at most half the sample rate, {} Hz (0 for all of it), found {}", sample_rate / 2,
                                   settings.f_max));
  }
  const double band_top = settings.f_max > 0 ? settings.f_max : sample_rate / 2;
  if (settings.f_min >= band_top) {
    spec.fail("f_min", fmt::format("a frequency below the band's top, {} Hz (f_max, or half the sample "
                                               "rate when f_max is 0)", band_top));
  }
  if (!settings.takes(segment)) {
    spec.fail("n_fft", fmt::format("a window {} the segment's {} samples (segment_seconds x sample_rate)",
                                               settings.center ? "shorter than twice" : "no longer than", segment));
  }
  return settings;
}

// Protocol defaults when dataset.json gives none: 5-way 5-shot, about 60% of classes in the base session.
SessionDefaults sessions_of(const DatasetFields& top, int classes, const SessionDefaults& fallback) {
  const DatasetFields spec = top.section("sessions");
  SessionDefaults defaults = fallback;
  if (defaults.sessions == 0) {
    const int incremental = std::max(1, classes * 2 / 5 / 5);
    const int way = std::min(5, (classes - 1) / incremental);  // fewer than 5 new classes a session in small sets
    defaults = {classes - way * incremental, way, 5, 1 + incremental};
  }
  const auto count = [&](const char* field, int fallback, const ValidRange& valid) {
    return static_cast<int>(spec.integer(field, valid, fallback));
  };
  defaults.base_classes = count("base_classes", defaults.base_classes, ValidRange::between(1, classes));
  defaults.way = count("way", defaults.way, ValidRange::between(1, classes));
  defaults.shot = count("shot", defaults.shot, ValidRange::between(1, kMaxShot));
  defaults.sessions = count("sessions", defaults.sessions, ValidRange::between(1, classes));
  // Classes no session takes would be in the data and in no result: say so rather than drop them.
  const std::int64_t used = defaults.base_classes + static_cast<std::int64_t>(defaults.way) * (defaults.sessions - 1);
  if (spec.has("sessions") && used != classes) {
    top.fail("sessions", fmt::format("a protocol over the {} classes of the manifest: base_classes {} + way {} x "
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
    const std::string key = item.substr(0, equals);
    const double value = parse_finite_float(item.substr(equals + 1), where + " context " + shown_text(item));
    if (!context.emplace(key, value).second) {
      throw DatasetError(fmt::format("{}: context '{}' gives '{}' twice, expected each key once", where,
                                     shown_text(text), shown_text(key)));
    }
    if (key == "held_out" && value != 0 && value != 1) {
      throw DatasetError(fmt::format("{}: context held_out={}, expected 1 (held out) or 0", where,
                                     shown_text(item.substr(equals + 1))));
    }
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
  const json document = read_dataset_json(fenced_by_root(root, config_path));
  const DatasetFields top(document, config_path.string());
  top.require_known_keys({"name", "sample_rate", "channels", "segment_seconds", "hop_seconds",
                          "max_segments_per_recording", "front_end", "sessions"});
  top.section("front_end").require_known_keys({"preset", "n_fft", "hop", "n_mels", "f_min", "f_max", "center"});
  top.section("sessions").require_known_keys({"base_classes", "way", "shot", "sessions"});

  DatasetScan scan;
  scan.root = root;
  DatasetDescription& d = scan.description;
  const auto expectation = [expected](auto field) {
    return expected ? std::optional(expected->*field) : std::nullopt;
  };
  d.name = field_or(top, "name", expectation(&FolderExpectation::name), [&] { return top.text("name"); });
  if (d.name.empty() || d.name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_.-") !=
                            std::string::npos) {
    top.fail("name", "letters, digits, '_', '.' or '-' (it names cache and result files)");
  }
  d.sample_rate = field_or(top, "sample_rate", expectation(&FolderExpectation::sample_rate),
                           [&] { return top.number("sample_rate", ValidRange::above_up_to(0, kMaxSampleRate)); });
  d.channel_names = field_or(top, "channels", expectation(&FolderExpectation::channels),
                             [&] { return top.names("channels"); });
  const double segment_seconds = field_or(top, "segment_seconds", expectation(&FolderExpectation::segment_seconds),
                                          [&] { return top.number("segment_seconds", ValidRange::above(0)); });
  const double hop_seconds = top.number("hop_seconds", ValidRange::above(0), segment_seconds);
  if (expected != nullptr) {
    require_value(config_path, "sample_rate", d.sample_rate, expected->sample_rate, expected->name);
    require_value(config_path, "channels", fmt::format("{}", fmt::join(d.channel_names, ",")),
                  fmt::format("{}", fmt::join(expected->channels, ",")), expected->name);
    require_value(config_path, "segment_seconds", segment_seconds, expected->segment_seconds, expected->name);
  }
  // Seconds as whole samples, bounded before the conversion (past int64 it would be undefined).
  const auto samples_of = [&](const char* field, double seconds) {
    const double samples = std::round(seconds * d.sample_rate);
    if (samples < 1 || samples > kMaxSegmentSamples) {
      top.fail(field, fmt::format("at least one and at most {:.0f} samples at sample_rate {} (it gives {:g})",
                                  kMaxSegmentSamples, d.sample_rate, samples));
    }
    return static_cast<std::int64_t>(samples);
  };
  const std::int64_t segment = samples_of("segment_seconds", segment_seconds);
  const std::int64_t hop = samples_of("hop_seconds", hop_seconds);
  d.segment = {segment, hop, top.integer("max_segments_per_recording", ValidRange::at_least(0), 0)};
  d.front_end = front_end_of(top.section("front_end"), d.sample_rate, segment, expected ? expected->preset : "");

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
  d.sessions = sessions_of(top, static_cast<int>(d.class_names.size()),
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
