#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/parameter_set.h"
#include "methods/common/precision.h"
#include "methods/method_registry.h"
#include "reports/run_record.h"

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
  // last | validation | test-oracle: how epochs are chosen where a reference code chooses them
  // (methods/method.h EpochSelection); test-oracle reproduces their habit of choosing on test.
  std::string selection = "last";
  // The sweep cell this command runs (fscil-bench sweep): recorded in every result.
  GridCell grid;
  // --save-embeddings: "" (none), "last", "all" or session numbers "0,9": the scored test
  // embeddings of those sessions go to OUT/embeddings/RUN.h5 (sessions: the saved session numbers;
  // session_S_embeddings N x D, session_S_labels; base_classes).
  std::string save_embeddings;
  // --save-model: each run's final method state in OUT/models/RUN.pt, a dict of named tensors for
  // Python's torch.load (protocols/saved_model.h).
  bool save_model = false;
  std::string max_memory;  // --max-memory SIZE (empty: none): passes that would pass it recompute activations
  std::string precision = "fp32";  // fp32 | bf16: what the shared encoder computes in (methods/common/precision.h)
  std::vector<std::string> assignments;  // --set key=value
  // What gave a --set key its value when the command line did not (`--config FILE: "set"`, `rerun
  // FILE: "parameters"`, a sweep cell's `--config FILE: "grid"`): an error in the value names it.
  std::map<std::string, std::string> assignment_origins;
  // A --config file's "set" values that the command line replaced: no run reads them, yet a read
  // of the key refuses nonsense in them too (ParameterSet::check_also).
  struct ReplacedAssignment {
    std::string key, value, origin;
  };
  std::vector<ReplacedAssignment> replaced_assignments;
  // rerun FILE: the file and the parameters it records. The runner writes every value a run reads,
  // so a run that would read one the file lacks is refused: the file was not written by a run, and
  // a default would stand in for the value it lost.
  std::string rerun_of;
  std::map<std::string, std::string> rerun_parameters;
  bool quiet = false;
  // --cell K (tools/fscil-bench/cells/bench_cells.h): this command is cell K of a plan, narrowed to its methods and
  // seed. It holds only that cell of --out, continues what --out holds of it, writes result files
  // and no tables (fscil-bench report merges them). -1: a whole command.
  int cell = -1;
};

// The main job: every method x seed through the protocol, one result file per run written as
// soon as it finishes, then summary.csv, results.tex and the rest; returns the Markdown tables
// (for a cell: where its result files are). Throws StopRequested after SIGTERM, its finished
// sessions kept in checkpoints.
std::string run_benchmark(const RunOptions& options);

// What `fscil-bench plan` estimates a command's time from, prepared as the command prepares it
// (the dataset from the cache, or built and cached; the same schedules): the input shape, the
// threads, the pretraining batch, each seed's run sizes and what each method read.
struct CommandSizes {
  std::int64_t channels = 0, mel_bins = 0, frames = 0;
  int threads = 0;
  Precision precision = Precision::fp32;
  std::int64_t pretraining_batch = 0;
  std::map<std::uint64_t, RunSizes> runs;  // by seed
  std::string cache_dir;                   // where this command caches (empty: --no-cache)
  std::map<std::string, ParameterSet> method_parameters;  // by method, as its run reads them
  std::string removal;  // describe_removal of the first seed's sessions ("" when they only add classes)
};
CommandSizes command_sizes(const RunOptions& options);

// Whether the command keeps and takes trained stages through the stage cache
// (protocols/stage_cache.h): a base session, or a stage methods share, trained before.
bool uses_stage_cache(const RunOptions& options);

// Sets LibTorch's intra-op threads (Debian's build starts with 1); returns the count used.
int configure_threads(int requested);

}  // namespace fscil
