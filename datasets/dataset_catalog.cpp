#include "datasets/dataset_catalog.h"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <algorithm>
#include <optional>

#include "core/error.h"
#include "datasets/finite_values.h"
#include "datasets/log_mel_extractor.h"
#include "datasets/readers/audio_adapters.h"
#include "datasets/readers/folder_adapter.h"
#include "datasets/readers/lmt108_adapter.h"
#include "datasets/readers/scanned_recordings.h"
#include "datasets/segment_cache.h"
#include "datasets/sf_instruments.h"
#include "datasets/simtex.h"
#include "core/parameter_set.h"
#include "core/text_file.h"

namespace fscil {

namespace {

namespace fs = std::filesystem;

struct RealDataset {
  const char* name;
  const char* summary;
  const char* where;
  const char* layout;
  DatasetScan (*scan)(const fs::path& root, const ParameterSet& params);
};

// Where each real dataset is published and which layout its adapter reads (PROTOCOLS.md).
const RealDataset kRealDatasets[] = {
    {"haptex", "HapTex fabrics: 120 classes, 5 channels at 1 kHz, 0.5 s segments (real data)",
     "the HapTex database of fabric textures (Jiao et al., IEEE World Haptics 2019)",
     "a generic tactile folder: dataset.json + manifest.csv (file,class,group,recording) + one CSV per "
     "recording with columns friction_force,normal_force,friction_coefficient,displacement,velocity (docs/real_datasets.md)",
     [](const fs::path& root, const ParameterSet&) { return scan_haptex(root); }},
    {"lmt108", "LMT108 surfaces: 108 classes, 3-axis acceleration at 10 kHz, 0.8 s segments (real data)",
     "the LMT Haptic Texture Database v1.1 (Strese et al., 2017)",
     "AccelScansComponents/Movement/{Training,Testing}/<Material>_Movement_{X,Y,Z}_{train,test}{1..10}.txt",
     scan_lmt108},
    {"ls100", "LS-100 speakers: 100 classes of 2 s LibriSpeech clips at 16 kHz (real data)",
     "LS-100 as built by the FSCIL audio benchmarks from LibriSpeech",
     "librispeech_fscil_{train,val,test}.csv with filename,speaker_id,label and the WAV files they name",
     [](const fs::path& root, const ParameterSet&) { return scan_ls100(root); }},
    {"ns100", "NS-100 instruments: 100 classes of 4 s NSynth notes at 16 kHz (real data)",
     "NS-100 as built by the FSCIL audio benchmarks from NSynth",
     "nsynth-100-fs-meta/nsynth-100-fs_{train,val,test}.csv (filename,instrument,audio_source), "
     "nsynth-100-fs-meta/nsynth-100-fs_vocab.json, <root>/<audio_source>/audio/<filename>.wav",
     [](const fs::path& root, const ParameterSet&) { return scan_ns100(root); }},
    {"folder", "any tactile recordings laid out as dataset.json + manifest.csv + per-recording CSV/TXT",
     "your own lab", "dataset.json + manifest.csv (file,class,group,recording[,split][,context]) (docs/real_datasets.md)",
     [](const fs::path& root, const ParameterSet&) { return scan_tactile_folder(root); }},
};

struct SimulatedDataset {
  const char* name;
  const char* summary;
  SimtexConfig (*config)();
  const char* preset;
  double segment_seconds;
  SessionDefaults sessions;
};

const SimulatedDataset kSimulatedDatasets[] = {
    {"simtex", "simulated HapTex-shaped textures: 120 classes, 5 channels, 1 kHz, 0.5 s, 100 per class",
     simtex_haptex_config, "haptex", 0.5, {75, 5, 5, 10}},
    {"simtex-lmt", "simulated LMT108-shaped textures: 108 classes, 3 channels, 10 kHz, 0.8 s, 120 per class",
     simtex_lmt_config, "lmt108", 0.8, {63, 5, 5, 10}},
    {"simtex-mini", "small simulated textures for tests: 20 classes, 5 channels, 1 kHz, 0.5 s, 30 per class",
     simtex_mini_config, "haptex", 0.5, {10, 5, 5, 3}},
};

// Built in and real: recorded instrument notes, rendered here (datasets/sf_instruments.h).
struct RenderedDataset {
  const char* name;
  const char* summary;
  int classes;
  int base_classes;
  double scale;  // the default
  int sessions;  // including the base session
  double seconds, hold_seconds;  // a clip, and how long its key is held
  // NS-100's protocol and front end, so the methods run with NS-100's released configuration too.
  const char* method_config = "ns100";
};

const RenderedDataset kRenderedDatasets[] = {
    {"sf-instruments", "recorded instrument notes rendered from MuseScore General: 100 GM programs, 4 s at 16 kHz, "
     "NS-100's protocol; a quarter of its clips (scale=0.25)", 100, 55, 0.25, 10, 4, 3},
    {"sf-instruments-mini", "sf-instruments for tests: 20 GM programs, 1 s notes, 10 base, 2 x 5-way 5-shot, 20 "
     "(base) or 15 (novel) clips per class (scale=0.05)", 20, 10, 0.05, 3, 1, 0.75},
};

LogMelSettings with_mel_options(LogMelSettings settings, const ParameterSet& params) {
  settings.scale = parse_mel_scale(params.choice("mel_scale", "htk", {"htk", "slaney"}));
  settings.norm = parse_mel_norm(params.choice("mel_norm", "none", {"none", "slaney"}));
  return settings;
}

bool keeps_features_in_memory(const SegmentSet& segments, const LogMelExtractor& extractor, FeatureStorage storage) {
  if (storage != FeatureStorage::automatic) return storage == FeatureStorage::in_memory;
  const auto& shape = segments.signals.shape;
  const std::int64_t bytes = shape[0] * shape[1] * extractor.settings().n_mels *
                             extractor.frames(shape[2]) * static_cast<std::int64_t>(sizeof(float));
  return bytes <= kInMemoryFeatureLimitBytes;
}

// A simulator or renderer driven past its range makes NaN or infinite samples: say so with its
// knobs before anything is cached (a cached file would fail every later run the same way).
void check_finite(const SegmentSet& segments, const DatasetDescription& description) {
  const FloatArray& signals = segments.signals;
  const std::int64_t i = first_non_finite(signals.values.data(), signals.size());
  if (i < 0) return;
  const std::int64_t row = i / signals.row_size();
  throw DatasetError(fmt::format("dataset '{}': recording '{}' has a non-finite sample ({}) as prepared from {}; "
                                 "finite signals expected: a data knob is out of its range; nothing was cached",
                                 description.name,
                                 segments.recording_ids[static_cast<std::size_t>(segments.recording_index[row])],
                                 signals.values[i], description.source));
}

// Loads the segments of `description` from the cache, or makes the recordings, cuts them and
// stores the segments (only when every step succeeded); then computes the features unless
// they are to be computed on demand.
PreparedDataset prepare_with_cache(const DatasetDescription& description, const DatasetRequest& request,
                                   std::ostream& log, const std::function<std::vector<Recording>()>& make_recordings) {
  const LogMelExtractor extractor(description.front_end);
  if (extractor.empty_filters() > 0) {
    fmt::print(log, "warning: {} of {} Mel filters are empty at n_fft={} (as torchaudio warns); "
               "their rows stay at -100 dB\n", extractor.empty_filters(), description.front_end.n_mels,
               description.front_end.n_fft);
  }
  PreparedDataset dataset;
  dataset.description = description;
  dataset.cache_key = SegmentCache::key_for(description);
  const SegmentCache cache(request.cache_dir);
  std::optional<SegmentSet> cached;
  if (!request.cache_dir.empty()) {
    // A damaged cache file is rebuilt; a folder or a device in its place is not the cache's to replace.
    const fs::path file = cache.path_for(description);
    if (const std::string why = why_not_a_regular_file(file); fs::exists(fs::symlink_status(file)) && !why.empty()) {
      throw DatasetError(fmt::format("{}: {}, where the segment cache keeps its file; move it away or choose another "
                                     "--cache-dir", file.string(), why));
    }
    std::string problem;
    cached = cache.load(description, &problem);
    if (!problem.empty()) fmt::print(log, "warning: {}; the cache file is rebuilt\n", problem);
  }
  if (cached) {
    dataset.segments = std::move(*cached);
  } else {
    dataset.segments = segment_recordings(make_recordings(), description.segment);
    check_finite(dataset.segments, description);
    if (!request.cache_dir.empty()) cache.store(description, dataset.segments);
  }
  if (keeps_features_in_memory(dataset.segments, extractor, request.features)) {
    dataset.features = extractor.extract(dataset.segments.signals, request.threads);
  } else {
    extractor.check_length(dataset.segments.signals.shape[2]);  // fail now, not in the middle of a run
  }
  return dataset;
}

PreparedDataset build_simulated(const SimulatedDataset& entry, const DatasetRequest& request,
                                const ParameterSet& params, std::ostream& log) {
  SimtexConfig config = entry.config();
  config.seed = static_cast<std::uint64_t>(params.integer("data_seed", 1, ValidRange::at_least(0)));
  // At 5 a recording's force spreads by e^{1.0 ε} and its direction by 75° per standard deviation,
  // and every recording has switched operator and device (p = min(1, 0.3 s)): past it the
  // contexts stop being ones a finger or a probe applies.
  config.context_strength = params.real("context_strength", config.context_strength, ValidRange::between(0, 5));
  config.context_shift = parse_context_shift(params.choice("context_shift", "none", {"none", "device", "speed"}));

  DatasetDescription description;
  description.name = entry.name;
  description.sample_rate = config.sample_rate;
  description.channel_names = config.channel_names();
  for (int y = 0; y < config.classes; ++y) description.class_names.push_back(fmt::format("material{:03d}", y));
  for (int g = 0; g < config.groups; ++g) description.group_names.push_back(fmt::format("family{:02d}", g));
  const auto segment_length = static_cast<std::int64_t>(entry.segment_seconds * config.sample_rate);
  description.segment = {segment_length, segment_length, 0};
  description.front_end = with_mel_options(log_mel_preset(entry.preset), params);
  description.sessions = entry.sessions;
  description.source = config.describe();
  return prepare_with_cache(description, request, log,
                            [&] { return generate_simtex(config, request.threads); });
}

PreparedDataset build_rendered(const RenderedDataset& entry, const DatasetRequest& request, const ParameterSet& params,
                               std::ostream& log) {
  SfInstrumentsConfig config;
  config.classes = entry.classes;
  config.base_classes = entry.base_classes;
  config.seconds = entry.seconds;
  config.hold_seconds = entry.hold_seconds;
  config.seed = static_cast<std::uint64_t>(params.integer("data_seed", 1, ValidRange::at_least(0)));
  config.scale = params.real("scale", entry.scale, ValidRange::between(0.05, 1));
  config.context_shift = parse_note_context_shift(params.choice("context_shift", "none", {"none", "pitch", "velocity"}));

  DatasetDescription description;
  description.name = entry.name;
  description.sample_rate = config.sample_rate;
  description.channel_names = {"mono"};
  description.channel_repeat = 3;  // as NS-100's: the ResNet sees the mono clip three times
  for (const int program : sf_instrument_programs(config)) description.class_names.push_back(fmt::format("gm{:03d}", program));
  for (int family = 0; family < kSfInstrumentFamilies; ++family) {
    description.group_names.push_back(fmt::format("gm_family{:02d}", family));
  }
  const auto length = static_cast<std::int64_t>(config.seconds * config.sample_rate);
  description.segment = {length, length, 1};  // one segment per clip, from its start
  description.front_end = with_mel_options(log_mel_preset("ns100"), params);
  description.sessions = {config.base_classes, 5, 5, entry.sessions};
  description.source = fmt::format("{} digest={}", config.describe(), soundfont_digest(config.soundfont, config.package));
  return prepare_with_cache(description, request, log, [&] { return render_sf_instruments(config, request.threads); });
}

PreparedDataset build_real(const RealDataset& entry, const DatasetRequest& request, const ParameterSet& params,
                           std::ostream& log) {
  if (request.data_root.empty()) {
    throw DataNotHere(fmt::format("dataset '{}' is real data and needs --data-root DIR: download {} "
                                   "and lay it out as {}", entry.name, entry.where, entry.layout));
  }
  if (const std::string why = why_not_a_folder(request.data_root); !why.empty()) {
    throw DataNotHere(fmt::format("--data-root {}: {} (expected a folder laid out as {})", request.data_root.string(),
                                   why, entry.layout));
  }
  DatasetScan scan = entry.scan(fs::canonical(request.data_root), params);
  DatasetDescription& description = scan.description;
  description.front_end = with_mel_options(description.front_end, params);
  refuse_files_outside_the_root(scan);
  description.source += fmt::format(" root={} {}", scan.root.string(), fingerprint_of(scan));
  return prepare_with_cache(description, request, log, [&] { return read_recordings(scan, request.threads); });
}

}  // namespace

FeatureStorage parse_feature_storage(const std::string& text) {
  if (text == "auto") return FeatureStorage::automatic;
  if (text == "memory") return FeatureStorage::in_memory;
  if (text == "on-demand") return FeatureStorage::on_demand;
  throw DatasetError(fmt::format("feature storage '{}': expected auto, memory or on-demand", text));
}

std::vector<CatalogEntry> dataset_catalog() {
  std::vector<CatalogEntry> entries;
  for (const auto& entry : kSimulatedDatasets) entries.push_back({entry.name, entry.summary, true, entry.name});
  for (const auto& entry : kRenderedDatasets) entries.push_back({entry.name, entry.summary, false, entry.method_config});
  for (const auto& entry : kRealDatasets) entries.push_back({entry.name, entry.summary, false, entry.name});
  return entries;
}

PreparedDataset prepare_dataset(const std::string& name, const DatasetRequest& request,
                                const ParameterSet& params, std::ostream& log) {
  // A data root given to a dataset that reads none is a mistake (a dataset name for another).
  const auto refuse_data_root = [&](const char* kind) {
    if (request.data_root.empty()) return;
    throw DatasetError(fmt::format("--data-root {}: dataset '{}' is {} and reads no data folder; leave --data-root "
                                   "out, or name the real dataset the folder holds", request.data_root.string(), name,
                                   kind));
  };
  for (const auto& entry : kSimulatedDatasets) {
    if (name == entry.name) return refuse_data_root("simulated"), build_simulated(entry, request, params, log);
  }
  for (const auto& entry : kRenderedDatasets) {
    if (name == entry.name) {
      return refuse_data_root("rendered from a soundfont"), build_rendered(entry, request, params, log);
    }
  }
  for (const auto& entry : kRealDatasets) {
    if (name == entry.name) return build_real(entry, request, params, log);
  }
  require_dataset_name(name);
  throw DatasetError(fmt::format("dataset '{}' has no builder", name));
}

void require_dataset_name(const std::string& name) {
  std::vector<std::string> names;
  for (const auto& entry : dataset_catalog()) names.push_back(entry.name);
  if (std::find(names.begin(), names.end(), name) != names.end()) return;
  throw DatasetError(fmt::format("unknown dataset '{}': expected one of {}", name, fmt::join(names, ", ")));
}

}  // namespace fscil
