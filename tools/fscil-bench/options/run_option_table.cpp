#include "tools/fscil-bench/options/run_option_table.h"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <map>
#include <type_traits>

#include "core/error.h"
#include "core/parallel_for.h"
#include "core/shown_text.h"
#include "datasets/dataset_catalog.h"
#include "protocols/session_plan.h"
#include "protocols/session_schedule.h"
#include "reports/run_record.h"
#include "tools/fscil-bench/options/cli_range.h"

namespace fscil {

const std::vector<RunOption>& run_option_table() {
  using R = RunOptions;
  using W = RunOption::Written;
  static const std::vector<RunOption> table = {
      {"--methods",
       "'all', 'ablation' (pits-sc and the four cop-fscil variants) or a comma-separated list of methods (see: "
       "fscil-bench list)",
       &R::methods, W::always, true},
      {"--dataset", "dataset name (see: fscil-bench list)", &R::dataset, W::always, true, {}, false, nullptr,
       require_dataset_name},
      {"--profile", "smoke | fast | paper", &R::profile, W::always, true, {}, true},
      {"--seeds", "seeds, e.g. 1,2,3 or 1-5", &R::seeds, W::always, true, {}, true},
      {"--threads", "compute threads (0 = all cores)", &R::threads, W::never, true, ValidRange::between(0, kMaxThreads),
       true},
      {"--out", "output directory for result files and tables", &R::out, W::always, false, {}, true,
       "expected a folder"},
      {"--features",
       "auto | memory | on-demand: keep log-Mel features in memory, or compute each batch from the signals (auto: in "
       "memory up to 1 GiB)",
       &R::features, W::always, false, {}, true, nullptr, [](const std::string& text) { parse_feature_storage(text); }},
      {"--split-mode", "recording (grouped, default) | segment", &R::split_mode, W::always, true, {}, true, nullptr,
       [](const std::string& text) { parse_split_mode(text); }},
      {"--class-order", "natural | shuffled (from the seed)", &R::class_order, W::always, true, {}, true, nullptr,
       require_class_order},
      {"--evaluate-on",
       "test | validation: score every session on the test split, or on the validation split of every class (choose "
       "defaults there, never on test)",
       &R::evaluate_on, W::always, true, {}, true, nullptr,
       [](const std::string& text) { parse_evaluation_split(text); }},
      {"--selection",
       "last | validation | test-oracle: which epoch a method keeps where the reference codes choose one (last: the "
       "last epoch; validation: the best on base validation; test-oracle: the best on the test split, as the "
       "reference codes do: inflated, labelled so in every table)",
       &R::selection, W::always, true, {}, true, nullptr,
       require_selection_name},
      {"--data-root", "root folder of a real dataset download", &R::data_root, W::when_given, false, {}, false,
       "expected a folder"},
      {"--cache-dir", "cache folder: segments, and trained base sessions under stages/ (default: ~/.cache/fscil-bench)",
       &R::cache_dir, W::when_given, false, {}, false,
       "expected a folder; leave the option out for ~/.cache/fscil-bench"},
      {"--no-cache", "neither read nor write either cache", &R::no_cache},
      {"--no-stage-cache", "train every base session, even one the cache holds for exactly these inputs",
       &R::no_stage_cache},
      {"--save-embeddings",
       "last | all | session numbers (0,9): keep the scored test embeddings of those sessions in OUT/embeddings/RUN.h5 "
       "(for the embedding figure of fscil-bench reproduce embedding)",
       &R::save_embeddings, W::when_given, false, {}, false,
       "expected last, all or session numbers (0,9); leave the option out to save none"},
      {"--save-model",
       "keep each run's final method state in OUT/models/RUN.pt: a dict of named tensors that Python's torch.load "
       "reads",
       &R::save_model},
      {"--max-memory",
       "SIZE (4G, 512M, bytes): a training pass that would take the run past it recomputes its ResNet stem and stages "
       "in backward (as --set recompute=stages, the same numbers), and freed large blocks go back to the kernel; an "
       "estimate, not a cap",
       &R::max_memory, W::when_given, true, {}, false, "expected a size such as 4G"},
      {"--precision",
       "fp32 | bf16: what the shared encoder computes in; bf16 runs its convolutions in bfloat16 (faster only on a "
       "CPU with AVX512-BF16 or AMX: fscil-bench plan says), other numbers than fp32, never in one table with fp32 runs",
       &R::precision, W::always, true, {}, true, nullptr,
       require_precision_name},
      {"--set", "override a hyper-parameter or knob: key=value (repeatable)", &R::assignments, W::when_given, true},
      {"--quiet", "no progress on stderr", &R::quiet},
      {"--cell",
       "run only cell K of this command (see: fscil-bench plan): its result files, no tables; continues what --out "
       "holds of it",
       &R::cell, W::never, true, ValidRange::at_least(0)},
  };
  return table;
}

void declare_run_options(CLI::App& app, RunOptions& options, const std::map<std::string, ChoiceReader>& more_readers) {
  for (const RunOption& row : run_option_table()) {
    std::visit(
        [&](auto member) {
          using Value = std::remove_reference_t<decltype(options.*member)>;
          if constexpr (std::is_same_v<Value, bool>) {
            app.add_flag(row.name, options.*member, row.help);
          } else {
            CLI::Option* option = app.add_option(row.name, options.*member, row.help);
            if (row.range) option->check(within(*row.range));
            if (row.shows_default) option->capture_default_str();
            if (row.if_empty != nullptr) option->check(refusing_empty(row.if_empty));
            const auto more = more_readers.find(row.name);
            if (const ChoiceReader read = more != more_readers.end() ? more->second : row.read_choice) {
              option->check(read_by(read));
            }
          }
        },
        row.member);
  }
}

std::vector<std::string> run_option_words(const RunOptions& options) {
  std::vector<std::string> words;
  for (const RunOption& row : run_option_table()) {
    if (row.written == RunOption::Written::never) continue;
    const bool always = row.written == RunOption::Written::always;
    std::visit(
        [&](auto member) {
          const auto& value = options.*member;
          using Value = std::decay_t<decltype(value)>;
          if constexpr (std::is_same_v<Value, bool>) {
            if (value) words.emplace_back(row.name);
          } else if constexpr (std::is_same_v<Value, std::string>) {
            if (always || !value.empty()) words.insert(words.end(), {row.name, value});
          } else if constexpr (std::is_same_v<Value, std::vector<std::string>>) {
            for (const auto& item : value) words.insert(words.end(), {row.name, item});
          } else {
            words.insert(words.end(), {row.name, std::to_string(value)});
          }
        },
        row.member);
  }
  return words;
}

void apply_assignments(const RunOptions& options, ParameterSet& params) {
  std::map<std::string, std::string> given;
  for (const auto& assignment : options.assignments) {
    const std::string key = assignment.substr(0, assignment.find('='));
    if (const auto earlier = given.find(key); earlier != given.end()) {
      throw CliError(fmt::format("--set {}: given twice ('{}', then '{}'); give each key once", shown_text(key),
                                 shown_text(earlier->second), shown_text(assignment)));
    }
    given.emplace(key, assignment);
    const auto origin = options.assignment_origins.find(key);
    params.set_assignment(assignment, origin == options.assignment_origins.end() ? "" : origin->second);
  }
  for (const auto& replaced : options.replaced_assignments) params.check_also(replaced.key, replaced.value, replaced.origin);
}

}  // namespace fscil
