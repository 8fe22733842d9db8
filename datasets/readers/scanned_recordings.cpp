#include "datasets/readers/scanned_recordings.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>

#include "core/error.h"
#include "core/parallel_for.h"
#include "datasets/segment_cache.h"

namespace fscil {

namespace fs = std::filesystem;

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
  return recordings;
}

}  // namespace fscil
