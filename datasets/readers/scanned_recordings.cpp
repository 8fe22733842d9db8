#include "datasets/readers/scanned_recordings.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <map>

#include "core/error.h"
#include "core/parallel_for.h"
#include "core/stable_hash.h"
#include "datasets/readers/regular_file.h"
#include "datasets/segment_cache.h"

namespace fscil {

namespace fs = std::filesystem;

void refuse_files_outside_the_root(const DatasetScan& scan) {
  const fs::path root = fs::weakly_canonical(scan.root);
  for (const auto& recording : scan.recordings) {
    for (const auto& file : recording.files) fenced_by_root(root, file);
  }
}

std::string fingerprint_of(const DatasetScan& scan) {
  std::string listing;
  std::size_t files = 0;
  for (const auto& recording : scan.recordings) {
    for (const auto& file : recording.files) {
      // An unreadable file gets the library's error values here; reading it fails later anyway.
      std::error_code ignored;
      const auto size = fs::file_size(file, ignored);
      const auto modified = fs::last_write_time(file, ignored).time_since_epoch().count();
      listing += fmt::format("{}|{}|{}\n", fs::relative(file, scan.root).string(), size, modified);
      ++files;
    }
  }
  return fmt::format("files={} fingerprint={}", files, stable_hash(listing));
}

namespace {

// Checked once the signals are read (only when the segment cache misses): equal samples, whatever
// the files' names, links or number formatting.
void refuse_identical(const DatasetScan& scan, const std::vector<Recording>& recordings) {
  std::map<std::string, std::vector<std::size_t>> by_digest;
  for (std::size_t r = 0; r < recordings.size(); ++r) {
    const auto& signal = recordings[r].signal;
    const std::string bytes(reinterpret_cast<const char*>(signal.data()), signal.size() * sizeof(float));
    auto& earlier = by_digest[fmt::format("{}:{}", recordings[r].channels, stable_hash(bytes))];
    for (std::size_t e : earlier) {
      if (recordings[e].signal != signal) continue;
      throw DatasetError(fmt::format("{}: recording '{}' has the same samples as recording '{}' ({}); a copy would put "
                                     "one signal on both sides of a split: list each recording once",
                                     scan.recordings[r].files.front().string(), recordings[r].id, recordings[e].id,
                                     scan.recordings[e].files.front().string()));
    }
    earlier.push_back(r);
  }
}

}  // namespace

std::vector<Recording> read_recordings(const DatasetScan& scan, int threads) {
  const std::size_t count = scan.recordings.size();
  if (count == 0) throw DatasetError(fmt::format("{}: no recordings found", scan.root.string()));
  const std::int64_t segment_length = scan.description.segment.length;
  std::vector<Recording> recordings(count);
  parallel_for(count, std::max(1, threads), [&](std::size_t r) {
    const RecordingSource& source = scan.recordings[r];
    SignalData signal = scan.read(source);
    if (signal.length < segment_length) {
      throw DatasetError(fmt::format("{}: {} samples, shorter than one segment of {} samples",
                                     source.files.front().string(), signal.length, segment_length));
    }
    Recording& recording = recordings[r];
    recording.id = source.id;
    recording.class_index = source.class_index;
    recording.group_index = source.group_index;
    recording.channels = signal.channels;
    recording.length = signal.length;
    recording.signal = std::move(signal.values);
    recording.context = source.context;
    recording.split_hint = source.split;
  });
  if (scan.refuse_identical_recordings) refuse_identical(scan, recordings);
  return recordings;
}

}  // namespace fscil
