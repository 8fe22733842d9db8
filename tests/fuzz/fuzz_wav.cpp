// Audio clips through libsndfile: a 16 kHz mono clip is read whole and finite, anything else
// (other formats, rates, channel counts, truncated or damaged headers) is a DatasetError.
#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "datasets/readers/wav_file.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace fscil;
  const auto path = fuzz::scratch_file("clip.wav", fuzz::text_of(data, size));
  fuzz::expect_only<DatasetError>([&] {
    const std::vector<float> samples = read_mono_audio(path, 16000);
    fuzz::require(!samples.empty() &&
                  std::all_of(samples.begin(), samples.end(), [](float v) { return std::isfinite(v); }));
  });
  return 0;
}
