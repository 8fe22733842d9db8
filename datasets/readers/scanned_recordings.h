#pragma once
#include <string>
#include <vector>

#include "datasets/readers/dataset_scan.h"

namespace fscil {

// Identifies the files behind a scan (relative path, size, modification time of each), so a
// cache entry is reused only while the data on disk is unchanged.
std::string fingerprint_of(const DatasetScan& scan);

// Throws DatasetError when a recording's file leads out of the scan's root through a symbolic link
// (before anything reads it).
void refuse_files_outside_the_root(const DatasetScan& scan);

// Reads every recording of a scan on `threads` threads. Throws the DatasetError of the first
// failing recording in scan order (so the message does not depend on thread timing); a
// recording too short for one segment is an error naming its file.
std::vector<Recording> read_recordings(const DatasetScan& scan, int threads);

}  // namespace fscil
