#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "reports/run_record.h"

namespace fscil {

// A smoke-profile run on two threads and AVX2 kernels with its session accuracies filled in, on a
// protocol of 10 base classes and 5 more per session, 5 test samples a class.
inline RunRecord run_with_accuracies(const std::string& method, const std::string& dataset, std::uint64_t seed,
                                     const std::vector<double>& accuracies) {
  RunRecord record;
  record.method = method;
  record.dataset = dataset;
  record.profile = "smoke";
  record.seed = seed;
  record.threads = 2;
  record.machine["kernels"] = "aten=AVX2 openblas=Haswell onednn=avx2";
  for (std::size_t s = 0; s < accuracies.size(); ++s) {
    SessionOutcome session;
    session.session = static_cast<int>(s);
    session.accuracy.all = accuracies[s];
    if (s == 0) session.accuracy.base = session.accuracy.current = accuracies[s];  // the base classes alone
    session.seen_classes = 10 + 5 * static_cast<int>(s);
    session.accuracy.samples = 5 * session.seen_classes;
    record.sessions.push_back(session);
  }
  return record;
}

// `record` as a run of the sweep cell `grid`, under the epoch selection `selection`.
inline RunRecord in_cell(RunRecord record, GridCell grid, const std::string& selection = "last") {
  record.grid = std::move(grid);
  record.selection = selection;
  return record;
}

}  // namespace fscil
