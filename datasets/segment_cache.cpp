#include "datasets/segment_cache.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>

#include "core/error.h"
#include "datasets/hdf5_file.h"
#include "core/number_text.h"

namespace fscil {

namespace {
// 2: segments only, no features; 3: with a digest of the contents; 4: metadata as attributes and
// variable-length strings, contexts as a float64 table (docs/datasets.md, "Files").
constexpr int kCacheFormat = 4;

std::vector<std::int32_t> to_int32(const std::vector<int>& values) { return {values.begin(), values.end()}; }
std::vector<int> to_int(const std::vector<std::int32_t>& values) { return {values.begin(), values.end()}; }

int split_code(SplitHint hint) { return static_cast<int>(hint); }
SplitHint split_from_code(int code, const std::filesystem::path& path) {
  if (code < 0 || code > static_cast<int>(SplitHint::validation)) {
    throw DatasetError(fmt::format("{}: recording split code {}, expected 0 to 3", path.string(), code));
  }
  return static_cast<SplitHint>(code);
}

// FNV-1a over 8-byte words (the tail byte by byte): a 120 MB cache digests in a few tens of ms.
class ContentDigest {
 public:
  void add(const void* data, std::size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (; bytes >= 8; p += 8, bytes -= 8) {
      std::uint64_t word;
      std::memcpy(&word, p, 8);
      mix(word);
    }
    for (; bytes > 0; ++p, --bytes) mix(*p);
    mix(0xff);  // so that moving bytes between two fields changes the digest
  }
  template <typename T>
  void add(const std::vector<T>& values) { add(values.data(), values.size() * sizeof(T)); }
  std::string hex() const { return fmt::format("{:016x}", hash_); }

 private:
  void mix(std::uint64_t value) {
    hash_ ^= value;
    hash_ *= 0x100000001b3ULL;
  }
  std::uint64_t hash_ = 0xcbf29ce484222325ULL;
};

std::string digest_of(const SegmentSet& s) {
  ContentDigest digest;
  for (const std::int64_t extent : s.signals.shape) digest.add(&extent, sizeof(extent));
  digest.add(s.signals.values);
  digest.add(s.class_index);
  digest.add(s.group_index);
  digest.add(s.recording_index);
  for (const auto& id : s.recording_ids) digest.add(id.data(), id.size());
  for (const SplitHint hint : s.recording_split) digest.add(&hint, sizeof(hint));
  for (const auto& name : s.context_names) digest.add(name.data(), name.size());
  digest.add(s.context_values);
  return digest.hex();
}

void require_in_range(const std::vector<int>& values, std::size_t end, const char* what,
                      const std::filesystem::path& path) {
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (values[i] < 0 || static_cast<std::size_t>(values[i]) >= end) {
      throw DatasetError(fmt::format("{}: segment {} has {} {}, expected 0 to {}", path.string(), i, what, values[i],
                                     static_cast<std::int64_t>(end) - 1));
    }
  }
}

// Shapes and index ranges against the dataset's description and within the file, so that a
// file of another shape never reaches the protocol.
void check_against(const SegmentSet& s, const DatasetDescription& d, const std::filesystem::path& path) {
  const auto& shape = s.signals.shape;
  const auto channels = static_cast<std::int64_t>(d.channel_names.size());
  if (shape[0] != s.count() || static_cast<std::int64_t>(s.group_index.size()) != s.count() ||
      static_cast<std::int64_t>(s.recording_index.size()) != s.count()) {
    throw DatasetError(fmt::format("{}: segment counts disagree between datasets", path.string()));
  }
  if (shape[1] != channels || shape[2] != d.segment.length) {
    throw DatasetError(fmt::format("{}: segments of {} channels x {} samples, expected {} x {}", path.string(), shape[1],
                                   shape[2], channels, d.segment.length));
  }
  require_in_range(s.class_index, d.class_names.size(), "class", path);
  require_in_range(s.group_index, std::max<std::size_t>(1, d.group_names.size()), "group", path);
  require_in_range(s.recording_index, s.recording_ids.size(), "recording", path);
  if (s.recording_split.size() != s.recording_ids.size() ||
      s.context_values.size() != s.recording_ids.size() * s.context_names.size()) {
    throw DatasetError(fmt::format("{}: per-recording lists disagree in length", path.string()));
  }
}
}  // namespace

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
    if (read_hdf5_attribute(path, "key") != key_for(description)) {
      throw DatasetError(fmt::format("{}: cache key mismatch", path.string()));
    }
    SegmentSet s;
    s.signals = read_hdf5_floats(path, "signals", 3);
    s.class_index = to_int(read_hdf5_integers(path, "class_index"));
    s.group_index = to_int(read_hdf5_integers(path, "group_index"));
    s.recording_index = to_int(read_hdf5_integers(path, "recording_index"));
    s.recording_ids = read_hdf5_strings(path, "recording_ids");
    for (int code : read_hdf5_integers(path, "recording_split")) s.recording_split.push_back(split_from_code(code, path));
    const std::string context_count = read_hdf5_attribute(path, "context_count");
    if (!parse_number<int>(context_count)) {
      throw DatasetError(fmt::format("{}: context_count '{}', expected a whole number", path.string(), context_count));
    }
    if (*parse_number<int>(context_count) > 0) {
      Hdf5Table contexts = read_hdf5_table(path, "contexts");
      s.context_names = std::move(contexts.columns);
      s.context_values = std::move(contexts.values);
    }
    check_against(s, description, path);
    if (read_hdf5_attribute(path, "digest") != digest_of(s)) {
      throw DatasetError(fmt::format("{}: contents differ from their digest (the file was altered)", path.string()));
    }
    return s;
  } catch (const DatasetError& error) {  // names the file already
    if (problem != nullptr) *problem = error.what();
    return std::nullopt;
  } catch (const std::exception& error) {  // its metadata is not what this format writes
    if (problem != nullptr) *problem = fmt::format("{}: unreadable metadata ({})", path.string(), error.what());
    return std::nullopt;
  }
}

void SegmentCache::store(const DatasetDescription& description, const SegmentSet& s) const {
  Hdf5Contents contents;
  contents.floats["signals"] = &s.signals;
  contents.integers["class_index"] = to_int32(s.class_index);
  contents.integers["group_index"] = to_int32(s.group_index);
  contents.integers["recording_index"] = to_int32(s.recording_index);
  for (SplitHint hint : s.recording_split) contents.integers["recording_split"].push_back(split_code(hint));
  contents.strings["recording_ids"] = s.recording_ids;
  contents.strings["channel_names"] = description.channel_names;
  contents.strings["class_names"] = description.class_names;
  if (!description.group_names.empty()) contents.strings["group_names"] = description.group_names;
  // An empty table would be a zero-width dataset: none is written, context_count says so.
  if (!s.context_names.empty()) contents.tables["contexts"] = {s.context_names, s.context_values};
  contents.attributes = {{"format_version", std::to_string(kCacheFormat)},
                         {"key", key_for(description)},
                         {"digest", digest_of(s)},
                         {"dataset", description.name},
                         {"source", description.source},
                         {"sample_rate", fmt::format("{}", description.sample_rate)},
                         {"segment_length", std::to_string(description.segment.length)},
                         {"segment_hop", std::to_string(description.segment.hop)},
                         {"segment_max_per_recording", std::to_string(description.segment.max_per_recording)},
                         {"front_end", description.front_end.describe()},
                         {"context_count", std::to_string(s.context_names.size())},
                         {"recording_split_codes", "0 none (the protocol splits), 1 train, 2 test, 3 validation"}};
  write_hdf5_atomically(path_for(description), contents);
}

}  // namespace fscil
