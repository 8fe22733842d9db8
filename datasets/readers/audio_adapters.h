#pragma once
#include <filesystem>

#include "datasets/readers/dataset_scan.h"

namespace fscil {

// LS-100 as the FSCIL audio benchmarks ship it (and PITS-SC reads it):
//   librispeech_fscil_{train,val,test}.csv with filename,speaker_id,label, and the WAV files
//   they name, relative to the root. 2 s mono clips at 16 kHz; label is the class (0-59 base).
DatasetScan scan_ls100(const std::filesystem::path& root);

// NS-100: nsynth-100-fs-meta/nsynth-100-fs_{train,val,test}.csv with filename,instrument,
//   audio_source, nsynth-100-fs-meta/nsynth-100-fs_vocab.json mapping instrument to class,
//   audio at <root>/<audio_source>/audio/<filename>.wav. 4 s mono notes at 16 kHz.
DatasetScan scan_ns100(const std::filesystem::path& root);

}  // namespace fscil
