#pragma once
#include <filesystem>
#include <vector>

namespace fscil {

// Reads a mono audio file (WAV or anything libsndfile knows) as floats in [-1, 1].
// Throws DatasetError naming the file for: missing or unreadable file, more than one channel,
// a sample rate other than `expected_rate` (no silent resampling), a header that promises more
// data than the file holds (truncated), no samples, or a NaN/Inf sample.
std::vector<float> read_mono_audio(const std::filesystem::path& path, double expected_rate);

}  // namespace fscil
