#pragma once
#include <string>

namespace fscil {

class ParameterSet;

// The released per-dataset hyper-parameters: the "set" block of configs/DATASET.json in the data
// folder (tools/fscil-bench/options/data_folder.h; PITS-SC's LS-100 and NS-100 configs: epochs, learning rates, CutMix
// probability, mixing alpha) as defaults, before the profile, which may shorten the epochs, and
// before --set. A dataset that follows a real one's protocol takes that one's file
// (CatalogEntry::method_config: sf-instruments runs with ns100's). Datasets without a file keep
// the tactile defaults. CliError naming the folder when
// the data folder has no configs/, and naming a file that is not a config.
void apply_dataset_defaults(const std::string& dataset, ParameterSet& params);

}  // namespace fscil
