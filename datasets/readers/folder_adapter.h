#pragma once
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "datasets/readers/dataset_scan.h"

namespace fscil {

// The generic tactile folder format any lab can write (docs/real_datasets.md):
//   dataset.json  name, sample_rate, channels, segment_seconds, [hop_seconds],
//                 [max_segments_per_recording], [front_end {preset, n_fft, hop, n_mels, center,
//                 f_min, f_max}], [sessions {base_classes, way, shot, sessions}]
//   manifest.csv  file,class,group,recording[,split][,context]
//   one CSV per recording (header of channel names, a row per sample), or one single-column
//   TXT per channel listed in `file` separated by ';'.
// Classes and groups are numbered in order of first appearance in the manifest.
DatasetScan scan_tactile_folder(const std::filesystem::path& root);

// HapTex laid out in the folder format: the same reader, with dataset.json held to HapTex's
// channels, 1 kHz and 0.5 s (fields it leaves out take these values) and the paper's protocol.
DatasetScan scan_haptex(const std::filesystem::path& root);

std::vector<std::string> haptex_channel_names();

}  // namespace fscil
