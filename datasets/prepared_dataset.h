#pragma once
#include <string>
#include <vector>

#include "datasets/float_array.h"
#include "datasets/log_mel_settings.h"
#include "datasets/segmenter.h"

namespace fscil {

// The FSCIL protocol a dataset is published with (PROTOCOLS.md); the CLI can override each value.
struct SessionDefaults {
  int base_classes = 0;
  int way = 5;
  int shot = 5;
  int sessions = 0;  // including the base session
};

struct DatasetDescription {
  std::string name;
  double sample_rate = 0;
  std::vector<std::string> channel_names;
  int channel_repeat = 1;  // the model sees each stored channel this many times (mono audio -> 3)
  std::vector<std::string> class_names;
  std::vector<std::string> group_names;
  SegmentSpec segment;
  LogMelSettings front_end;
  SessionDefaults sessions;
  std::string source;  // what produced the recordings (simulator settings or adapter + root)
};

// Segments and their log-Mel features, ready for a protocol.
struct PreparedDataset {
  DatasetDescription description;
  SegmentSet segments;
  FloatArray features;  // N x C x n_mels x frames; empty when features are computed on demand
  std::string cache_key;

  bool features_on_demand() const { return features.shape.empty(); }
};

}  // namespace fscil
