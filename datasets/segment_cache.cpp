#include "datasets/segment_cache.h"

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "datasets/dataset_error.h"
#include "datasets/hdf5_file.h"

namespace fscil {

namespace {
constexpr int kCacheFormat = 2;  // 2: segments only, no features

std::vector<std::int32_t> to_int32(const std::vector<int>& values) { return {values.begin(), values.end()}; }
std::vector<int> to_int(const std::vector<std::int32_t>& values) { return {values.begin(), values.end()}; }

int split_code(SplitHint hint) { return static_cast<int>(hint); }
SplitHint split_from_code(int code) {
  if (code < 0 || code > static_cast<int>(SplitHint::validation)) {
    throw DatasetError(fmt::format("recording split code {}: expected 0 to 3", code));
  }
  return static_cast<SplitHint>(code);
}
}  // namespace

std::string stable_hash(const std::string& text) {
  std::uint64_t hash = 0xcbf29ce484222325ULL;
  for (unsigned char c : text) {
    hash ^= c;
    hash *= 0x100000001b3ULL;
  }
  return fmt::format("{:016x}", hash);
}

std::string SegmentCache::key_for(const DatasetDescription& d) {
  return stable_hash(fmt::format("format={}|name={}|source={}|segment={},{},{}", kCacheFormat, d.name, d.source,
                                 d.segment.length, d.segment.hop, d.segment.max_per_recording));
}

std::filesystem::path SegmentCache::path_for(const DatasetDescription& description) const {
  return directory_ / fmt::format("{}-{}.h5", description.name, key_for(description));
}

std::optional<SegmentSet> SegmentCache::load(const DatasetDescription& description, std::string* problem) const {
  const auto path = path_for(description);
  if (!std::filesystem::exists(path)) return std::nullopt;
  try {
    const auto meta = nlohmann::json::parse(read_hdf5_text(path, "meta"));
    if (meta.at("key").get<std::string>() != key_for(description)) {
      throw DatasetError(fmt::format("{}: cache key mismatch", path.string()));
    }
    SegmentSet s;
    s.signals = read_hdf5_floats(path, "signals", 3);
    s.class_index = to_int(read_hdf5_integers(path, "class_index"));
    s.group_index = to_int(read_hdf5_integers(path, "group_index"));
    s.recording_index = to_int(read_hdf5_integers(path, "recording_index"));
    s.recording_ids = meta.at("recording_ids").get<std::vector<std::string>>();
    for (int code : meta.at("recording_split").get<std::vector<int>>()) s.recording_split.push_back(split_from_code(code));
    s.context_names = meta.at("context_names").get<std::vector<std::string>>();
    const FloatArray context = read_hdf5_floats(path, "context_values", 1);
    s.context_values.assign(context.values.begin(), context.values.end());
    if (s.signals.shape[0] != s.count()) {
      throw DatasetError(fmt::format("{}: segment counts disagree between datasets", path.string()));
    }
    return s;
  } catch (const std::exception& error) {
    if (problem != nullptr) *problem = error.what();
    return std::nullopt;
  }
}

void SegmentCache::store(const DatasetDescription& description, const SegmentSet& s) const {
  Hdf5Contents contents;
  FloatArray context({static_cast<std::int64_t>(s.context_values.size())});
  std::copy(s.context_values.begin(), s.context_values.end(), context.values.begin());
  contents.floats["signals"] = &s.signals;
  contents.floats["context_values"] = &context;
  contents.integers["class_index"] = to_int32(s.class_index);
  contents.integers["group_index"] = to_int32(s.group_index);
  contents.integers["recording_index"] = to_int32(s.recording_index);
  std::vector<int> splits;
  for (SplitHint hint : s.recording_split) splits.push_back(split_code(hint));
  nlohmann::json meta = {{"key", key_for(description)},
                         {"recording_ids", s.recording_ids},
                         {"recording_split", splits},
                         {"context_names", s.context_names}};
  contents.texts["meta"] = meta.dump();
  write_hdf5_atomically(path_for(description), contents);
}

}  // namespace fscil
