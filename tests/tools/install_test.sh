#!/usr/bin/env bash
# The install tree works on its own, and the tool configures without the test libraries:
#   install_test.sh SOURCE_DIR BUILD_DIR WORK
set -euo pipefail
source_dir="$1"
build_dir="$2"
work="$3"
fail() {
  echo "FAIL: $*" >&2
  exit 1
}
rm -rf "$work"
mkdir -p "$work"
prefix="$work/prefix"
cmake --install "$build_dir" --prefix "$prefix" >"$work/install.log" || fail "cmake --install: $(tail -n 3 "$work/install.log")"
for file in bin/fscil-bench share/fscil-bench/reports/reference/paper_tables.csv \
  share/fscil-bench/reports/reference/paper_analyses.csv share/fscil-bench/configs/ls100.json \
  share/man/man1/fscil-bench.1 share/bash-completion/completions/fscil-bench share/doc/fscil_bench/LICENSE \
  share/doc/fscil_bench/CITATION.cff; do
  [ -f "$prefix/$file" ] || fail "$prefix/$file: not installed"
done
# The installed binary reads its data from the prefix, not from the source tree it was built from.
version="$(cd / && "$prefix/bin/fscil-bench" --version)"
echo "$version" | grep -qx "  data       $prefix/share/fscil-bench" || fail "--version names another data folder: $version"
grep -qF -- '\-\-missing\-only' "$prefix/share/man/man1/fscil-bench.1" || fail "the man page lacks the subcommands' options"
echo "installed into $prefix; --version: $(echo "$version" | head -n 1), data in $prefix/share/fscil-bench"

# Without the tests, neither GoogleTest nor Google Benchmark is looked for.
cmake -S "$source_dir" -B "$work/no-tests" -DBUILD_TESTING=OFF -DCMAKE_DISABLE_FIND_PACKAGE_GTest=ON \
  -DCMAKE_DISABLE_FIND_PACKAGE_benchmark=ON >"$work/configure.log" 2>&1 ||
  fail "configure with BUILD_TESTING=OFF and no GTest/benchmark: $(grep -m 3 -i error "$work/configure.log")"
echo "configures with BUILD_TESTING=OFF and GTest, benchmark made unfindable"
