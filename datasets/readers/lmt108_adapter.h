#pragma once
#include <filesystem>

#include "datasets/readers/dataset_scan.h"

namespace fscil {

class ParameterSet;

// The LMT Haptic Texture Database v1.1 (Strese et al. 2017) as downloaded:
//   AccelScansComponents/Movement/{Training,Testing}/<Material>_Movement_{X,Y,Z}_{train,test}<n>.txt
// one value per line at 10 kHz. Materials are classes, their G1..G9 prefix the group. The
// database's testing recordings carry SplitHint::test, so they never give training segments or shots.
// `lmt108_signals` (accel | accel+friction | accel+sound | accel+friction+sound) adds the
// friction channel (FricScans/**/<Material>_FrictionFSR1_Movement_<split><n>.txt) and the sound
// channel (SoundScans/**/<Material>_*_<split><n>.wav, which must already be at 10 kHz).
DatasetScan scan_lmt108(const std::filesystem::path& root, const ParameterSet& params);

}  // namespace fscil
