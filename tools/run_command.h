#pragma once
#include <string>
#include <vector>

namespace fscil {

struct RunOptions {
  std::string methods;
  std::string dataset;
  std::string profile = "fast";
  std::string seeds = "1";
  int threads = 0;  // 0 = every hardware thread
  std::string out = "results";
  bool resume = false;  // continue the run whose --out this is: keep finished runs, continue checkpoints
  std::string data_root;
  std::string cache_dir;  // empty = the user cache directory
  bool no_cache = false;        // neither cache: segments nor trained base sessions
  bool no_stage_cache = false;  // train every base session here (protocols/stage_cache.h)
  std::string features = "auto";  // auto | memory | on-demand (datasets/dataset_catalog.h)
  std::string split_mode = "recording";
  std::string class_order = "natural";
  std::string evaluate_on = "test";  // test | validation: the split every session is scored on
  std::string max_memory;  // --max-memory SIZE (empty: none): passes that would pass it recompute activations
  std::vector<std::string> assignments;  // --set key=value
  bool quiet = false;
};

// The main job: every method x seed through the protocol, one result file per run written as
// soon as it finishes, then summary.csv, results.tex and a Markdown table on stdout.
void run_benchmark(const RunOptions& options);

// Sets LibTorch's intra-op threads (Debian's build starts with 1); returns the count used.
int configure_threads(int requested);

}  // namespace fscil
