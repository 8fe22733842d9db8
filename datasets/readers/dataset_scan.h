#pragma once
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "datasets/prepared_dataset.h"
#include "datasets/readers/signal_data.h"
#include "datasets/recording.h"

namespace fscil {

// A recording as an adapter finds it on disk, before any signal is read.
struct RecordingSource {
  std::string id;
  int class_index = 0;
  int group_index = 0;
  SplitHint split = SplitHint::none;
  std::map<std::string, double> context;
  std::vector<std::filesystem::path> files;  // every file its signal is read from
};

// What an adapter learns from a real dataset's layout (names, classes, files) without reading
// the signals, so the cache can be consulted first; `read` then loads one recording.
struct DatasetScan {
  std::filesystem::path root;
  DatasetDescription description;
  std::vector<RecordingSource> recordings;
  std::function<SignalData(const RecordingSource&)> read;
  // Refuse two recordings with the same samples (a copy under another name would put one signal
  // on both sides of a split): the folder format, whose manifests users write by hand.
  bool refuse_identical_recordings = false;
};

}  // namespace fscil
