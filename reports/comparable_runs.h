#pragma once
#include <string>
#include <vector>

#include "reports/run_record.h"

namespace fscil {

// Why runs `a` and `b` cannot share a table, or "" when they can. Runs of one dataset must agree
// on its data (dataset key), profile, scored split, thread count and protocol parameters (way,
// shot, context, ...); runs of one method on one dataset must agree on every parameter. Runs of
// different datasets, and of different sweep cells, can (they are different rows) when they were
// made in one precision (--precision).
std::string incomparability(const RunRecord& a, const RunRecord& b);

// Throws ReportError naming both files and the first difference when two of `records` cannot
// share a table (averaged as seeds of one row, a 5-shot and a 3-shot run would mislead), or when
// one method, dataset and seed is there twice.
void require_comparable_runs(const std::vector<RunRecord>& records);

}  // namespace fscil
