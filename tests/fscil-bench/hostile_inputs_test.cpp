// Bad inputs and faults as a user or an attacker tries them, one row each: the command, its exit
// code, a fragment of its one error line, and the promise that it changed no file (nothing in
// --out, the cache or the user's files is written, replaced or removed). The next round of hostile
// inputs starts from this table.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <ostream>
#include <string>
#include <vector>

#include "core/stable_hash.h"
#include "tests/fscil-bench/cli_support.h"
#include "tests/temporary_directory.h"

namespace fscil {
namespace {

namespace fs = std::filesystem;

struct HostileCase {
  const char* name;
  std::string arguments;  // {root} stands for a fresh folder holding out/ (with a user's file) and cache/
  int exit_code;
  const char* fragment;   // of the one error line
  // More files under {root} before the command: "name/" a folder, "name=@path" a copy of the
  // source tree's file, "name=text" a file holding text, "name->target" a symbolic link ({root}
  // allowed in target), "name|" a FIFO, "name" a file of the user's.
  std::vector<std::string> files = {};
  std::string environment = "";  // shell words before the command: "ulimit -f 100;"
};

// gtest names a case by this (ctest lists it), not by the struct's bytes.
void PrintTo(const HostileCase& c, std::ostream* out) { *out << c.name; }

// Every file below `root` with a digest of its content: what must come out of a refused command
// exactly as it went in.
std::map<std::string, std::string> tree_of(const fs::path& root) {
  std::map<std::string, std::string> tree;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    const std::string name = fs::relative(entry.path(), root).string();
    const fs::file_status node = entry.symlink_status();
    tree[name] = fs::is_symlink(node)         ? "link to " + fs::read_symlink(entry.path()).string()
                 : fs::is_regular_file(node) ? stable_hash(read_text(entry.path()))
                 : fs::is_fifo(node)         ? std::string("FIFO")
                                             : std::string("folder");
  }
  return tree;
}

std::string with_root(std::string arguments, const fs::path& root) {
  for (std::size_t at; (at = arguments.find("{root}")) != std::string::npos;) {
    arguments.replace(at, 6, root.string());
  }
  return arguments;
}

const std::string kRun = "--methods prototype --dataset simtex-mini --profile smoke --threads 1 --quiet "
                         "--out {root}/out --cache-dir {root}/cache ";

// A run whose refusal comes after its data is prepared: no cache to write first.
const std::string kNoCacheRun = "--methods prototype --dataset simtex-mini --profile smoke --threads 1 --quiet --no-cache "
                                "--out {root}/out ";

const std::string kFolderRun = "--methods prototype --dataset folder --data-root {root}/data --profile smoke "
                               "--threads 1 --quiet --no-cache --out {root}/out ";
// Segments of 3 samples and a front end that fits them (a centred window of 4, one Mel filter).
const std::string kLabHead = R"(data/dataset.json={"name": "lab", "sample_rate": 100, "channels": ["a"], )"
                             R"("segment_seconds": 0.03)";
const std::string kLabJson = kLabHead + R"(, "front_end": {"n_fft": 4, "n_mels": 1, "center": true})";
const std::vector<std::string> kTwoClasses = {"data/manifest.csv=file,class,group,recording\nr0.csv,a,g,r0\nr1.csv,b,g,r1\n",
                                              "data/r0.csv=a\n1\n2\n3\n", "data/r1.csv=a\n10\n20\n30\n"};

// A run's folder as fscil-bench leaves it: its .lock and one result file.
const std::vector<std::string> kOrcoRun = {"runs/.lock", "runs/results/orco.json=@tests/fuzz/corpus/run_record/orco_smoke.json"};
// A reference CSV's header, as "reference" writes it; the rows follow.
const std::string kReferenceCsv = "ref.csv=method,dataset,profile,seed,threads,kernels,metric,expected,tolerance\n";

// " --grid key=0,1,...,values-1" for each key: a grid of values^keys cells.
std::string grid_of(const std::string& keys, int values) {
  std::string grid;
  for (char key : keys) {
    grid += std::string(" --grid ") + key + "=0";
    for (int v = 1; v < values; ++v) grid += "," + std::to_string(v);
  }
  return grid;
}

std::string repeated(const std::string& text, int times) {
  std::string all;
  for (int i = 0; i < times; ++i) all += text;
  return all;
}

// "grid.json=..." : a config sweeping shot over `values` values.
std::string grid_config(int values) {
  std::string file = R"(grid.json={"grid": {"shot": [0)";
  for (int v = 1; v < values; ++v) file += "," + std::to_string(v);
  return file + "]}}";
}

std::vector<std::string> with(std::vector<std::string> files, const std::string& more) {
  files.push_back(more);
  return files;
}

const HostileCase kCases[] = {
    // A failed preparation writes no cache: simulator knobs have physical ranges.
    {"context_strength_far_out_of_range", kRun + "--set context_strength=1e300", 1,
     "parameter context_strength='1e300': expected a number in [0, 5]"},
    {"context_strength_past_its_physical_range", kRun + "--set context_strength=1000", 1,
     "parameter context_strength='1000': expected a number in [0, 5]"},
    {"context_strength_negative", kRun + "--set context_strength=-1", 1,
     "parameter context_strength='-1': expected a number in [0, 5]"},
    // The user's files are the user's: a folder that was never an --out (no .lock) keeps its tables.
    {"out_holding_the_users_summary", kRun, 1, "out/summary.csv would be replaced, and nothing says fscil-bench wrote it",
     {"out/summary.csv"}},
    {"out_holding_the_users_page", kRun, 1, "out/index.html would be replaced", {"out/index.html", "out/results/"}},
    {"report_into_the_users_folder", "report --results {root}/runs --out {root}/out", 1,
     "out/results.tex would be replaced", with(kOrcoRun, "out/results.tex")},
    {"plain_run_into_a_sweeps_folder", kRun, 1, "a sweep's folder (it has cells/)", {"out/.lock", "out/cells/"}},
    // Sizes bounded before work, and no script line from an option.
    {"sweep_of_billions_of_cells",
     "sweep --methods prototype --dataset simtex-mini --profile smoke --quiet --out {root}/out" + grid_of("abcd", 255),
     2, "--grid: 4228250625 cells (255 x 255 x 255 x 255) are more than the 10000 a sweep takes"},
    {"sbatch_arg_setting_the_array",
     "slurm --methods prototype --dataset simtex-mini --profile smoke --out {root}/out --sbatch-arg=--array=0-99", 2,
     "--sbatch-arg --array=0-99: --array is fscil-bench's to set"},
    {"partition_holding_a_command",
     "slurm --methods prototype --dataset simtex-mini --profile smoke --out {root}/out --partition 'cpu\ntouch PWNED'",
     2, "--partition 'cpu\\ntouch PWNED': expected a Slurm partition name"},
    // Leakage a copy can hide.
    {"manifest_path_out_of_the_dataset", kFolderRun, 1, "file '../r1.csv' is outside the dataset folder",
     {kLabJson + "}", "data/manifest.csv=file,class,group,recording\nr0.csv,a,g,r0\n../r1.csv,b,g,r1\n",
      "data/r0.csv=a\n1\n2\n3\n", "r1.csv=a\n10\n20\n30\n"}},
    {"recording_copied_under_another_name", kFolderRun, 1, "r1.csv: recording 'r1' has the same samples as recording 'r0'",
     {kLabJson + "}", "data/manifest.csv=file,class,group,recording\nr0.csv,a,g,r0\nr1.csv,b,g,r1\n",
      "data/r0.csv=a\n1\n2\n3\n", "data/r1.csv=a\n1\n2\n3\n"}},
    // Formats read strictly: a typo or a repeat is not a default.
    {"dataset_json_unknown_field", kFolderRun, 1, "unknown field 'sampel_rate', expected one of name, sample_rate",
     with(kTwoClasses, kLabJson + R"(, "sampel_rate": 1000})")},
    {"dataset_json_unknown_front_end_field", kFolderRun, 1, "unknown field 'front_end.nfft'",
     with(kTwoClasses, kLabHead + R"(, "front_end": {"nfft": 64}})")},
    // dataset.json's values checked against each other before any recording is read, the file named.
    {"dataset_json_band_past_nyquist", kFolderRun, 1,
     "dataset.json: field 'front_end.f_max': expected at most half the sample rate, 50 Hz (0 for all of it), found 500",
     with(kTwoClasses, kLabHead + R"(, "front_end": {"n_fft": 4, "center": true, "f_max": 500}})")},
    {"manifest_with_a_column_twice", kFolderRun, 1, "manifest.csv:1: column 'class' appears twice in the header",
     {kLabJson + "}", "data/manifest.csv=file,class,group,recording,class\nr0.csv,a,g,r0,z\nr1.csv,b,g,r1,z\n",
      "data/r0.csv=a\n1\n2\n3\n", "data/r1.csv=a\n10\n20\n30\n"}},
    {"dataset_json_sample_rate_past_any_sensor", kFolderRun, 1,
     "dataset.json: field 'sample_rate': expected a number in (0, 10000000]",
     with(kTwoClasses, R"(data/dataset.json={"name": "lab", "sample_rate": 1e300, "channels": ["a"], "segment_seconds": 1})")},
    {"dataset_json_segment_of_a_billion_samples", kFolderRun, 1,
     "field 'segment_seconds': expected at least one and at most 100000000 samples at sample_rate 10000000",
     with(kTwoClasses, R"(data/dataset.json={"name": "lab", "sample_rate": 1e7, "channels": ["a"], "segment_seconds": 100})")},
    {"dataset_json_unknown_preset", kFolderRun, 1,
     "dataset.json: field 'front_end.preset': expected one of haptex, lmt108, ls100, ns100",
     with(kTwoClasses, kLabHead + R"(, "front_end": {"preset": "bogus"}})")},
    {"dataset_json_window_longer_than_a_segment", kFolderRun, 1,
     "dataset.json: field 'front_end.n_fft': expected a window no longer than the segment's 3 samples",
     with(kTwoClasses, kLabHead + "}")},
    {"dataset_json_band_upside_down", kFolderRun, 1,
     "dataset.json: field 'front_end.f_min': expected a frequency below the band's top, 40 Hz",
     with(kTwoClasses, kLabHead + R"(, "front_end": {"n_fft": 3, "f_min": 60, "f_max": 40}})")},
    {"dataset_json_field_twice", kFolderRun, 1, "field 'sample_rate' given twice in one object",
     with(kTwoClasses, kLabJson + R"(, "sample_rate": 1000})")},
    {"dataset_json_a_folder", kFolderRun, 1, "dataset.json: a folder, not a file", with(kTwoClasses, "data/dataset.json/")},
    {"sessions_leaving_classes_out", kFolderRun, 1, "base_classes 1 + way 1 x (sessions 1 - 1) takes 1",
     with(kTwoClasses, kLabJson + R"(, "sessions": {"sessions": 1}})")},
    {"resume_a_folder_no_command_wrote", "--methods prototype --dataset simtex-mini --profile smoke --quiet "
     "--resume {root}/empty", 2, "no fscil-bench command wrote there (no .lock, no result files), nothing to resume",
     {"empty/"}},
    // A folder where fscil-bench keeps a file is named as what it is, not as a damaged file.
    {"cache_file_a_folder", kRun, 1,
     "simtex-mini-9ab4d58d62532ddd.h5: a folder, not a file, where the segment cache keeps its file",
     {"cache/simtex-mini-9ab4d58d62532ddd.h5/"}},
    {"checkpoint_a_folder", "--methods prototype --dataset simtex-mini --profile smoke --quiet --no-cache "
     "--resume {root}/run", 1, "prototype__simtex-mini__seed1.ckpt: a folder, not a file, expected a checkpoint file",
     {"run/.lock", "run/checkpoints/prototype__simtex-mini__seed1.ckpt/"}},
    {"set_value_with_a_plus_sign", "--methods prototype --dataset simtex-mini --profile smoke --quiet --no-cache "
     "--out {root}/out --set shot=+5", 1,
     "parameter shot='+5': expected the number without '+' (the value's text names the run, and '5' would be another)"},
    {"set_integer_with_a_leading_zero", "--methods prototype --dataset simtex-mini --profile smoke --quiet --no-cache "
     "--out {root}/out --set shot=05", 1,
     "parameter shot='05': expected the integer as 5 (the value's text names the run)"},
    // A line break in a path is spelled out, not cut at: the line names the file and the reason.
    {"config_path_with_a_line_break", kRun + "--config '{root}/a\nb.json'", 1, "a\\nb.json: cannot open"},
    // A path past the line's 2000 characters loses its middle, not the reason at its end.
    {"config_path_of_3000_characters", kRun + "--config {root}/" + repeated(std::string(198, 'd') + "/", 15) + "x.json",
     1, "x.json: cannot open (No such file or directory)"},
    {"set_key_twice", kRun + "--set pretrain_epochs=1 --set pretrain_epochs=2", 2, "--set pretrain_epochs: given twice"},
    // Past 2^63 a config's number was once read back as -1.
    {"config_integer_past_int64", "--methods prototype --dataset simtex-mini --profile smoke --quiet --no-cache "
     "--out {root}/out --config {root}/run.json", 1,
     "run.json: \"set\".shot='18446744073709551615': expected an integer",
     {R"(run.json={"set": {"shot": 18446744073709551615}})"}},
    {"config_key_twice", kRun + "--config {root}/run.json", 2, "key 'shot' given twice",
     {R"(run.json={"set": {"shot": 5, "shot": 3}})"}},
    {"resume_with_other_seeds",
     "--methods prototype --dataset simtex-mini --profile smoke --threads 1 --quiet --no-cache --seeds 2 --resume {root}/out",
     1, "prototype__simtex-mini__seed1.ckpt is the checkpoint of a run this command does not make",
     {"out/.lock", "out/checkpoints/prototype__simtex-mini__seed1.ckpt"}},
    // Round four. A failed write is one error line, never a crash (HDF5 once segfaulted at exit).
    {"segment_cache_past_a_file_size_limit", kRun, 1, "MiB (File too large)", {}, "ulimit -f 100;"},
    // Inputs that are not files: a FIFO with no writer once blocked for ever.
    {"config_a_fifo", kRun + "--config {root}/run.json", 1, "run.json: expected a regular file, found a FIFO",
     {"run.json|"}},
    // Bounds before work: 300 000 values of one key once took 110 s of CPU to reach the refusal.
    {"grid_of_300000_values_in_a_config",
     "plan --methods prototype --dataset simtex-mini --profile smoke --out {root}/out --config {root}/grid.json", 2,
     "--grid shot: 300000 values are more than the 10000 cells a sweep takes", {grid_config(300000)}},
    // Result files name what this program runs: a table never carries a method nothing here can run.
    {"report_of_a_method_nothing_runs", "report --results {root}/runs --out {root}/tables", 1,
     "unknown.json: field 'method': expected a method this program runs (fscil-bench list), found 'bogus-method'",
     {"runs/.lock", "runs/results/unknown.json=@tests/fuzz/corpus/run_record/unknown_method.json"}},
    {"analyze_of_a_method_nothing_runs", "analyze --results {root}/runs --out {root}/tables", 1,
     "found 'bogus-method'; an out-of-tree method's results are tabulated by its own program",
     {"runs/.lock", "runs/results/unknown.json=@tests/fuzz/corpus/run_record/unknown_method.json", "tables/"}},
    {"result_file_a_folder", "report --results {root}/runs --out {root}/tables", 1,
     "runs/results/x.json: a folder, not a file, expected a result file",
     with(kOrcoRun, "runs/results/x.json/")},
    {"paper_tables_without_paper", "report --results {root}/runs --out {root}/tables --paper-tables {root}/runs/.lock", 2,
     "--paper-tables: read only with --paper", kOrcoRun},
    // Every cell checked before the first one trains or is listed.
    {"sweep_with_a_bad_value_in_its_last_cell", "sweep --methods prototype --dataset simtex-mini --profile smoke --quiet "
     "--no-cache --threads 1 --grid shot=1,nan --out {root}/sweep", 1, "parameter shot='nan': expected an integer"},
    {"plan_listing_an_unknown_dataset", "plan --no-estimate --methods prototype --dataset nonsense", 2,
     "--dataset 'nonsense': expected one of"},
    // A reference file's typo is the file's fault, not the results' drift.
    {"reference_with_an_unknown_metric", "check --results {root}/runs --reference {root}/ref.csv", 1,
     "ref.csv:2: metric 'bogus', expected acc_0, acc_1, ... (a session's accuracy), AA, PD or ADR",
     with(kOrcoRun, kReferenceCsv + "orco,simtex-mini,smoke,1,1,k,bogus,60,2\n")},
    {"reference_with_a_value_twice", "check --results {root}/runs --reference {root}/ref.csv", 1,
     "ref.csv:3: orco on simtex-mini seed 1 (1 threads, k) acc_0 given again (line 2 gives it)",
     with(kOrcoRun, kReferenceCsv + "orco,simtex-mini,smoke,1,1,k,acc_0,60,2\n"
                              "orco,simtex-mini,smoke,1,1,k,acc_0,10,2\n")},
    // The one writer replaces regular files only, and never a file the command reads.
    {"reference_out_onto_the_result_it_reads",
     "reference --results {root}/runs --out {root}/runs/results/orco.json", 2, "runs/results/orco.json: inside ",
     kOrcoRun},
    {"reference_out_onto_a_link", "reference --results {root}/runs --out {root}/out/link.csv", 1,
     "link.csv: is a symbolic link; fscil-bench writes only regular files",
     with(kOrcoRun, "out/link.csv->{root}/elsewhere.csv")},
    {"reference_out_onto_a_fifo", "reference --results {root}/runs --out {root}/out/pipe", 1,
     "pipe: is a FIFO; fscil-bench writes only regular files",
     with(kOrcoRun, "out/pipe|")},
    {"reference_out_onto_a_device", "reference --results {root}/runs --out /dev/full", 1,
     "/dev/full: is a character device; fscil-bench writes only regular files",
     kOrcoRun},
    {"rerun_into_the_original_folder", "rerun {root}/runs/results/orco.json --out {root}/runs", 2,
     "runs holds this result file, which the rerun would replace",
     kOrcoRun},
    // Every file fscil-bench writes below --out is claimed before work, not the tables alone.
    {"out_holding_the_users_checkpoint", kRun, 1, "checkpoints/prototype__simtex-mini__seed1.ckpt would be replaced",
     {"out/checkpoints/prototype__simtex-mini__seed1.ckpt"}},
    {"out_holding_the_users_figure", kRun, 1, "figures/sessions_simtex-mini.svg would be replaced",
     {"out/figures/sessions_simtex-mini.svg"}},
    {"out_holding_a_file_named_results", kRun, 1, "out/results is not a folder, and fscil-bench writes its results there",
     {"out/results"}},
    // Options a run would ignore, or read as another, are refused.
    {"cache_dir_empty", kRun + "--cache-dir ''", 2, "--cache-dir: expected a folder; leave the option out"},
    {"resume_empty", "--methods prototype --dataset simtex-mini --profile smoke --quiet --resume ''", 2,
     "--resume: expected the folder of the interrupted command"},
    {"cache_dir_with_no_cache", kRun + "--no-cache", 2, "--cache-dir and --no-cache: --no-cache reads and writes no cache"},
    {"data_root_of_a_simulated_dataset", kRun + "--data-root {root}/out", 1,
     "dataset 'simtex-mini' is simulated and reads no data folder"},
    {"embeddings_of_one_session_twice", kRun + "--save-embeddings 0,0", 2, "--save-embeddings 0,0: session 0 given twice"},
    {"data_root_a_file", "--methods prototype --dataset haptex --profile smoke --quiet --no-cache --out {root}/out "
     "--data-root {root}/out/notes.txt", 1, "notes.txt: a file, not a folder (expected a folder laid out as"},
    {"selection_fixed_and_swept",
     "plan --methods prototype --dataset simtex-mini --profile smoke --out {root}/out --selection validation "
     "--grid selection=last,test-oracle --no-estimate", 2, "--selection validation and --grid selection: a choice is either"},
    // Every cell is checked before it is listed, scripted or started: once, not in every task.
    {"plan_with_a_grid_key_no_one_reads",
     "plan --methods prototype --dataset simtex-mini --profile smoke --no-cache --out {root}/out --grid bogus=1,2", 1,
     "--grid bogus: no dataset, protocol or method of this run reads it"},
    {"slurm_with_a_grid_value_no_run_takes",
     "slurm --methods prototype --dataset simtex-mini --profile smoke --no-cache --out {root}/out --time 1:00:00 "
     "--grid shot=0,1", 1, "shot"},
    {"run_cells_with_a_value_no_run_takes",
     "run-cells --methods prototype --dataset simtex-mini --profile smoke --no-cache --quiet --seeds 1-2 "
     "--out {root}/out --set shot=0", 1, "shot"},
    // report reads what the command it names wrote, and says so when the folder holds something else.
    {"report_of_a_method_the_folder_lacks", "report --results {root}/runs --methods orco,prototype --out {root}/tables", 2,
     "runs holds no result file of prototype",
     kOrcoRun},
    {"report_with_a_grid_the_folder_lacks", "report --results {root}/runs --grid shot=1,5 --out {root}/tables", 2,
     "--grid: ", kOrcoRun},
    // Recordings read as strictly as dataset.json: no sample lost to a blank line, no range called "not a number".
    {"recording_with_a_blank_line_between_samples", kFolderRun, 1,
     "r0.csv:3: a blank line between samples (line 4 follows it)",
     {kLabJson + "}", "data/manifest.csv=file,class,group,recording\nr0.csv,a,g,r0\nr1.csv,b,g,r1\n",
      "data/r0.csv=a\n1\n\n2\n3\n", "data/r1.csv=a\n10\n20\n30\n\n\n"}},
    {"recording_with_a_sample_past_float_range", kFolderRun, 1,
     "r0.csv:3 column a: 1e39 is outside the range of a 32-bit float sample",
     {kLabJson + "}", "data/manifest.csv=file,class,group,recording\nr0.csv,a,g,r0\nr1.csv,b,g,r1\n",
      "data/r0.csv=a\n1\n1e39\n3\n", "data/r1.csv=a\n10\n20\n30\n"}},
    // Round five (issue 66's plan and resume work, read by a helper): numbers that would wrap, nest or
    // repeat are refused before work.
    {"set_integer_past_an_int", "--methods prototype --dataset simtex-mini --profile smoke --quiet --no-cache --out {root}/out --set way=4294967301", 1,
     "parameter way='4294967301': expected an integer >= 1 and at most 2147483647"},
    {"set_way_as_large_as_an_int", "--methods prototype --dataset simtex-mini --profile smoke --quiet --no-cache --out {root}/out --set way=2147483647", 1,
     "session plan needs 4294967304 classes (10 base + 2 adding sessions x 2147483647-way) but the dataset has 20"},
    {"result_file_nested_a_hundred_thousand_deep", "report --results {root}/runs --out {root}/tables", 1,
     "deep.json: arrays and objects nested more than 64 deep, expected a fscil-bench file",
     with(kOrcoRun, "runs/results/deep.json=" + std::string(100000, '[') + std::string(100000, ']'))},
    {"config_nested_a_hundred_thousand_deep", kRun + "--config {root}/run.json", 2,
     "run.json: arrays and objects nested more than 64 deep, expected run options",
     {"run.json={\"set\": " + std::string(100000, '[') + std::string(100000, ']') + "}"}},
    // Round six (a helper's probe of the built program): a config's values are named by the file,
    // checked even where the command line replaces them, and never read as another number.
    {"config_set_value_a_boolean", kNoCacheRun + "--config {root}/run.json", 1,
     "run.json: \"set\".shot='true': expected an integer", {R"(run.json={"set": {"shot": true}})"}},
    {"config_set_value_replaced_on_the_command_line", kNoCacheRun + "--config {root}/run.json --set shot=5", 1,
     "run.json: \"set\".shot='abc': expected an integer", {R"(run.json={"set": {"shot": "abc"}})"}},
    {"config_number_too_small_for_a_double", kRun + "--config {root}/run.json", 2,
     "run.json: the number 1e-400 is too small for a double (it would be read as 0)",
     {R"(run.json={"set": {"context_strength": 1e-400}})"}},
    {"config_grid_value_a_boolean", "sweep " + kNoCacheRun + "--config {root}/run.json", 1,
     "run.json: \"grid\".shot='true': expected an integer", {R"(run.json={"grid": {"shot": [5, true]}})"}},
    {"config_grid_value_out_of_range_in_run_cells", "run-cells --jobs 2 " + kNoCacheRun + "--config {root}/run.json", 1,
     "run.json: \"grid\".shot='0': expected an integer", {R"(run.json={"grid": {"shot": [5, 0]}})"}},
    // Round seven: an option and a --set or --grid of the parameter it sets; the --set value won
    // without a word, and a sweep dropped the option.
    {"class_order_by_option_and_set", kRun + "--class-order shuffled --set class_order=natural", 2,
     "--class-order shuffled and --set class_order='natural': both set class_order; give it once"},
    {"split_mode_by_option_and_grid", "plan " + kRun + "--split-mode segment --grid split_mode=segment,recording", 2,
     "--split-mode segment and --grid split_mode=segment,recording: a parameter is either fixed or swept"},
    {"methods_with_a_trailing_comma",
     "--methods prototype, --dataset simtex-mini --profile smoke --threads 1 --quiet --no-cache --out {root}/out", 2,
     "--methods prototype,: an empty name after the last comma"},
    {"methods_all_beside_a_method",
     "--methods all,prototype --dataset simtex-mini --profile smoke --threads 1 --quiet --no-cache --out {root}/out", 2,
     "--methods all,prototype: 'all' stands alone"},
    {"save_embeddings_empty", kNoCacheRun + "--save-embeddings ''", 2,
     "--save-embeddings: expected last, all or session numbers (0,9); leave the option out to save none"},
    {"report_out_empty", "report --results {root}/runs --out ''", 2,
     "--out: expected a folder; leave the option out for the results folder", kOrcoRun},
    {"reference_out_empty", "reference --results {root}/runs --out ''", 2, "--out: expected a file", kOrcoRun},
    // A result file's numbers are read as the runner wrote them, or refused: a count past what a
    // double holds came back as -9223372036854775808, and a training log no run writes (an epoch
    // twice, below 1, control characters in a stage) was copied into logs/*.csv.
    {"result_with_test_samples_past_two_to_the_53", "report --results {root}/runs --out {root}/tables", 1,
     "test_samples 9223372036854775807, expected a whole number from 0 to 9007199254740992",
     {"runs/.lock", "runs/results/x.json=@tests/fuzz/corpus/run_record/test_samples_past_two_to_the_53.json"}},
    {"result_with_a_training_log_epoch_twice", "report --results {root}/runs --out {root}/tables", 1,
     "expected each epoch of stage 'pretrain' once, found epoch 1 again",
     {"runs/.lock", "runs/results/x.json=@tests/fuzz/corpus/run_record/training_log_epoch_twice.json"}},
    {"reproduce_list_with_a_name", "reproduce bogus --list", 2, "reproduce bogus --list: give a NAME or --list, not both"},
    {"reproduce_list_with_run_options", "reproduce --list --dataset simtex --seeds 3-1", 2,
     "reproduce --list: --dataset is read only when a reproduction runs"},
    // Round seven: a report that fails part-way (a full disk, a folder in a file's place) once left
    // new tables beside old figures and an old page; its files replace the old ones together.
    {"report_failing_at_its_last_file", "report --results {root}/runs --out {root}/tables", 1,
     "tables/index.html: is a directory, a file was expected",
     with(with(kOrcoRun, "tables/.lock"), "tables/index.html/")},
    // Round seven: an output inside the results folder's results/ broke that folder for every
    // later report, analyze and check.
    {"report_out_among_the_result_files", "report --results {root}/runs --out {root}/runs/results/tables.json", 2,
     "runs/results/tables.json: inside ", kOrcoRun},
    {"report_out_among_the_result_files_named", "report --results {root}/runs --out {root}/runs/results/x", 2,
     "runs/results/, which holds a run's own files; every later command reading",
     kOrcoRun},
    {"analyze_out_the_result_folder_itself", "analyze --results {root}/runs --out {root}/runs/results", 2,
     "runs/results: inside ", kOrcoRun},
    {"report_out_among_the_result_files_through_a_missing_folder",
     "report --results {root}/runs --out {root}/missing/../runs/results/x", 2, "runs/results/x: inside ", kOrcoRun},
    {"reference_out_among_the_result_files", "reference --results {root}/runs --out {root}/runs/results/ref.json", 2,
     "runs/results/ref.json: inside ", kOrcoRun},
    // Round seven: the words came back last first ("'prototype --methods'").
    {"analyze_with_words_it_does_not_take", "analyze --results {root}/runs --methods prototype", 2,
     "'--methods prototype': not an option, value or subcommand this command takes", kOrcoRun},
    {"analyze_out_holding_the_users_file", "analyze --results {root}/runs --out {root}/mine", 1,
     "mine/context_analysis.csv would be replaced, and nothing says fscil-bench wrote it",
     with(kOrcoRun, "mine/context_analysis.csv=the user's own\n")},
    {"reference_out_holding_the_users_file", "reference --results {root}/runs --out {root}/mine.csv", 1,
     "mine.csv: would be replaced, and it is not a reference CSV", with(kOrcoRun, "mine.csv=the user's own\n")},
    {"config_asking_for_help", kRun + "--config {root}/run.json", 2, "run.json: \"help\": not a run option",
     {R"(run.json={"help": true})"}},
    {"config_asking_for_the_version", kRun + "--config {root}/run.json", 2, "run.json: \"version\": not a run option",
     {R"(run.json={"version": true})"}},
    // A result file is what the runner writes, or it is refused naming itself: rerun and check never
    // read a parameter no run could have used.
    {"rerun_of_a_parameter_not_finite", "rerun {root}/runs/results/odd.json --out {root}/again", 1,
     "odd.json: field 'parameters.temperature': 'nan', expected a finite number",
     {"runs/.lock", "runs/results/odd.json=@tests/fuzz/corpus/run_record/parameter_not_finite.json"}},
    {"reference_with_a_tolerance_past_100", "check --results {root}/runs --reference {root}/ref.csv", 1,
     "ref.csv:2: tolerance 1e30, expected percentage points in [0, 100]",
     with(kOrcoRun, kReferenceCsv + "orco,simtex-mini,smoke,1,1,k,acc_0,60,1e30\n")},
    {"reference_with_an_accuracy_past_100", "check --results {root}/runs --reference {root}/ref.csv", 1,
     "ref.csv:2: acc_0 of 150, expected a value in [0, 100]",
     with(kOrcoRun, kReferenceCsv + "orco,simtex-mini,smoke,1,1,k,acc_0,150,2\n")},
    // The data root fences what a dataset reads, links resolved.
    {"recording_linked_out_of_the_data_root", kFolderRun, 1, "leads to /etc/passwd, outside the data root",
     {kLabJson + "}", "data/manifest.csv=file,class,group,recording\nr0.csv,a,g,r0\nr1.csv,b,g,r1\n",
      "data/r0.csv=a\n1\n2\n3\n", "data/r1.csv->/etc/passwd"}},
};

class HostileInput : public testing::TestWithParam<HostileCase> {};

TEST_P(HostileInput, FailsWithOneLineAndChangesNoFile) {
  const HostileCase& c = GetParam();
  TemporaryDirectory root;
  fs::create_directories(root.path() / "out");
  fs::create_directories(root.path() / "cache");
  std::ofstream(root.path() / "out" / "notes.txt") << "the user's own notes\n";
  for (const std::string& file : c.files) {
    const auto equals = file.find('=');
    const auto arrow = file.find("->");
    if (arrow != std::string::npos) {
      fs::create_directories((root.path() / file.substr(0, arrow)).parent_path());
      fs::create_symlink(with_root(file.substr(arrow + 2), root.path()), root.path() / file.substr(0, arrow));
      continue;
    }
    const fs::path path = root.path() / file.substr(0, equals);
    fs::create_directories(path.parent_path());
    if (file.back() == '|') {
      ASSERT_EQ(::mkfifo((root.path() / file.substr(0, file.size() - 1)).c_str(), 0644), 0) << file;
    } else if (equals != std::string::npos && file.compare(equals, 2, "=@") == 0) {
      fs::copy_file(source_folder() / file.substr(equals + 2), path);
    } else if (equals != std::string::npos) {
      std::ofstream(path) << file.substr(equals + 1);
    } else if (file.back() != '/') {
      std::ofstream(path) << "the user's " << file << "\n";
    }
  }
  const auto before = tree_of(root.path());

  const CommandResult result = run_cli(with_root(c.arguments, root.path()), c.environment);
  expect_one_error_line(result, c.fragment);
  EXPECT_EQ(result.exit_code, c.exit_code) << result.output;
  EXPECT_EQ(tree_of(root.path()), before) << "files changed by: " << c.arguments;
}

// Round seven: plan's calibration once allocated --set batch_size samples (64 TB here) and died
// with LibTorch's 30-frame trace; training never takes a batch larger than its samples, and
// neither does the calibration now.
TEST(HostileInput, APlanOfABatchLargerThanTheDataIsEstimatedAsTrainingRunsIt) {
  TemporaryDirectory root;
  const CommandResult plan = run_cli("plan --methods prototype --dataset simtex-mini --profile smoke --threads 1 --quiet "
                                     "--no-cache --out " + (root.path() / "out").string() + " --set batch_size=2147483647");
  EXPECT_EQ(plan.exit_code, 0) << plan.output;
  EXPECT_NE(plan.output.find("estimated "), std::string::npos) << plan.output;
}

// Round seven: a 300 MB result file took 1.3 GB of memory before its error line; a few GB would
// have been killed. A file past any result's size is refused before it is read (a sparse file here).
TEST(HostileInput, AResultFileLargerThanAnyResultIsRefusedUnread) {
  TemporaryDirectory root;
  fs::create_directories(root.path() / "runs" / "results");
  std::ofstream(root.path() / "runs" / ".lock");
  const fs::path huge = root.path() / "runs" / "results" / "huge.json";
  std::ofstream(huge) << "{}";
  fs::resize_file(huge, (64u << 20) + 1);
  for (const std::string command : {"report", "analyze", "reference"}) {
    const CommandResult result = run_cli(command + " --results " + (root.path() / "runs").string() + " --out " +
                                         (root.path() / (command == "reference" ? "ref.csv" : "tables")).string());
    expect_one_error_line(result, "huge.json: 67108865 bytes, expected a result file of at most 67108864 bytes");
    EXPECT_EQ(result.exit_code, 1) << command;
  }
  const CommandResult rerun = run_cli("rerun " + huge.string() + " --out " + (root.path() / "again").string());
  expect_one_error_line(rerun, "huge.json: 67108865 bytes, expected a result file of at most");
  EXPECT_FALSE(fs::exists(root.path() / "again"));
}

// Round seven: the command reference writes as its CSV's comment (and check prints) is quoted for a
// shell, and a path it cannot write on one line is refused before anything is written.
TEST(HostileInput, TheRegenerateCommandIsQuotedAndALineBreakInItsPathRefused) {
  TemporaryDirectory root;
  const std::string run = "--methods prototype --dataset simtex-mini --profile smoke --threads 1 --quiet --no-cache --out ";
  const fs::path odd = root.path() / "a $(id)";
  ASSERT_EQ(run_cli(run + "'" + odd.string() + "'").exit_code, 0);
  const fs::path csv = root.path() / "ref.csv";
  ASSERT_EQ(run_cli("reference --results '" + odd.string() + "' --out " + csv.string()).exit_code, 0);
  EXPECT_NE(read_text(csv).find("# Regenerate (never in CI): fscil-bench reference --results '" + odd.string() + "' --out "),
            std::string::npos) << read_text(csv);

  const fs::path broken = root.path() / "a\nmethod,x";
  fs::rename(odd, broken);
  const CommandResult refused = run_cli("reference --results '" + broken.string() + "' --out " +
                                        (root.path() / "second.csv").string());
  expect_one_error_line(refused, "a line break in the path");
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_FALSE(fs::exists(root.path() / "second.csv"));
}

// System errors carry the path and the system's reason, not the library's "filesystem error: status:"
// (apart from the table: its tree walk cannot pass a loop of links either).
TEST(HostileInput, ALoopOfLinksIsNamedWithTheSystemsReason) {
  TemporaryDirectory root;
  fs::create_symlink(root.path() / "loop2", root.path() / "loop1");
  fs::create_symlink(root.path() / "loop1", root.path() / "loop2");
  const CommandResult result = run_cli("--methods prototype --dataset simtex-mini --profile smoke --quiet --no-cache --out " +
                                       (root.path() / "loop1").string());
  expect_one_error_line(result, "loop1/cells: Too many levels of symbolic links");
  EXPECT_EQ(result.output.find("filesystem error"), std::string::npos) << result.output;
  EXPECT_EQ(result.exit_code, 1);
}

// report, analyze, check and reference wait for no one: while a command still writes the folder,
// its tables would count the runs finished so far as all of them.
TEST(OutFolder, TablesAreRefusedWhileACommandStillWritesTheFolder) {
  TemporaryDirectory root;
  fs::create_directories(root.path() / "runs" / "results");
  fs::copy_file(source_folder() / "tests/fuzz/corpus/run_record/orco_smoke.json", root.path() / "runs/results/orco.json");
  for (const char* lock : {".lock", ".lock-orco__simtex-mini__seed2"}) {
    const int held = ::open((root.path() / "runs" / lock).c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    ASSERT_GE(held, 0);
    ASSERT_EQ(::flock(held, LOCK_EX | LOCK_NB), 0);
    const std::string results = (root.path() / "runs").string();
    for (const std::string& command : {"report --results " + results + " --out " + (root.path() / "tables").string(),
                                       "analyze --results " + results + " --out " + (root.path() / "tables").string()}) {
      const CommandResult busy = run_cli(command);
      expect_one_error_line(busy, std::string("a fscil-bench command is still writing there (") + lock + " is held)");
    }
    ::close(held);
  }
  EXPECT_FALSE(fs::exists(root.path() / "tables" / "summary.csv"));
  // Released (the command ended, kill -9 included), the same folder is tabulated.
  EXPECT_EQ(run_cli("report --results " + (root.path() / "runs").string()).exit_code, 0);
}

// temperature=1e-45 once trained at chance (loss 2.3026 every epoch), exited 0 as if measured, and
// filed the degenerate base in the stage cache for every later run.
// A finished run's result file is an input of the command that would make it again: refused before
// any work (it once trained everything, then failed to write), the earlier result kept to the byte.
TEST(OutFolder, TheSameRunAgainIsRefusedBeforeAnyWorkAndResumeKeepsIt) {
  TemporaryDirectory root;
  const std::string out = (root.path() / "out").string();
  const std::string run = "--methods prototype --dataset simtex-mini --profile smoke --threads 1 --no-cache --quiet ";
  ASSERT_EQ(run_cli(run + "--out " + out).exit_code, 0);
  const fs::path result = root.path() / "out" / "results" / "prototype__simtex-mini__seed1.json";
  const std::string before = read_text(result);
  const CommandResult again = run_cli(run + "--seeds 1-2 --out " + out);
  expect_one_error_line(again, "prototype__simtex-mini__seed1.json holds a run of this command already (prototype, "
                               "seed 1); --resume " + out + " keeps it");
  EXPECT_FALSE(fs::exists(root.path() / "out" / "checkpoints" / "prototype__simtex-mini__seed1.ckpt"))
      << "refused before training";
  EXPECT_EQ(read_text(result), before);
  EXPECT_FALSE(fs::exists(root.path() / "out" / "results" / "prototype__simtex-mini__seed2.json"));
  ASSERT_EQ(run_cli(run + "--seeds 1-2 --resume " + out).exit_code, 0);
  EXPECT_EQ(read_text(result), before);
  EXPECT_TRUE(fs::exists(root.path() / "out" / "results" / "prototype__simtex-mini__seed2.json"));
}

TEST(DegenerateTraining, ABaseThatDidNotLearnIsMarkedAndNeverCached) {
  TemporaryDirectory root;
  const CommandResult run = run_cli("--methods pits-sc --dataset simtex-mini --profile smoke --threads 1 --set "
                                    "temperature=1e-45 --out " + (root.path() / "out").string() + " --cache-dir " +
                                    (root.path() / "cache").string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("training not learning (pretrain: its loss stayed at 2.3026"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("stages not shared or cached: pretrain"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("base session not cached: its training did not learn"), std::string::npos) << run.output;
  EXPECT_NE(read_text(root.path() / "out" / "summary.csv").find(",not learning,\n"), std::string::npos);
  EXPECT_FALSE(fs::exists(root.path() / "cache" / "stages") && !fs::is_empty(root.path() / "cache" / "stages"));
}

// What the refusals must leave alone: folders fscil-bench wrote, with or without their .lock.
TEST(OutFolder, FoldersFscilBenchWroteStayUsable) {
  TemporaryDirectory root;
  const std::string out = (root.path() / "out").string(), tables = (root.path() / "tables").string();
  const std::string run = "--methods prototype --dataset simtex-mini --profile smoke --threads 1 --quiet --no-cache ";
  ASSERT_EQ(run_cli(run + "--out " + out).exit_code, 0);
  fs::remove(root.path() / "out" / ".lock");  // a folder from before the .lock, or copied without it
  const CommandResult resumed = run_cli(run + "--resume " + out);
  EXPECT_EQ(resumed.exit_code, 0) << resumed.output;
  for (int time = 0; time < 2; ++time) {
    const CommandResult report = run_cli("report --results " + out + " --out " + tables);
    EXPECT_EQ(report.exit_code, 0) << report.output;
  }
  // A config file's bad value is named as the file's, not as a flag the user never typed.
  std::ofstream(root.path() / "run.json") << R"({"threads": "two"})";
  expect_one_error_line(run_cli("--methods prototype --dataset simtex-mini --profile smoke --quiet --no-cache --config " +
                                (root.path() / "run.json").string() + " --out " + out),
                        "run.json: \"threads\": expected a number in [0, 256]");
}

INSTANTIATE_TEST_SUITE_P(Table, HostileInput, testing::ValuesIn(kCases),
                         [](const testing::TestParamInfo<HostileCase>& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace fscil
