#!/usr/bin/env bash
# tools/check_floors.sh passes on the tree and fails, naming file, line and arrow, on a copy of it
# with one upward include (core/ including protocols/) and one sideways (reports/ including methods/).
#   bash tests/tools/check_floors_test.sh SOURCE_DIR WORK_DIR
set -euo pipefail
source_dir=$1
work=$2
fail() { echo "FAIL: $*" >&2; exit 1; }

bash "$source_dir/tools/check_floors.sh" "$source_dir" || fail "the tree itself has an include that does not point down"

rm -rf "$work"
mkdir -p "$work"
for floor in core metrics datasets methods protocols reports tools; do cp -r "$source_dir/$floor" "$work/"; done
bash "$source_dir/tools/check_floors.sh" "$work" > /dev/null || fail "an unchanged copy fails"

printf '#pragma once\n#include "protocols/profiles.h"\n' > "$work/core/upward.h"
printf '#include <vector>\n\n#include "core/shown_text.h"\n#include "methods/method.h"\n' > "$work/reports/sideways.cpp"
if output=$(bash "$source_dir/tools/check_floors.sh" "$work"); then fail "an upward include passed: $output"; fi
echo "$output"
grep -qx 'core/upward.h:2: core/ includes protocols/ (core/ may include: nothing)' <<< "$output" || fail "upward arrow not named"
grep -qx 'reports/sideways.cpp:4: reports/ includes methods/ (reports/ may include: core metrics datasets)' <<< "$output" \
  || fail "sideways arrow not named"
[ "$(wc -l <<< "$output")" -eq 2 ] || fail "expected exactly the two arrows"
echo "check_floors: catches both arrows"
