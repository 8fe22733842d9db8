#!/usr/bin/env bash
# Builds the libFuzzer targets of tests/fuzz (clang 14, AddressSanitizer + UBSan) into build-fuzz/
# and runs each for SECONDS on a scratch copy of its seed corpus, printing one line per target.
# Exits non-zero naming the target and the input kept for any finding (crash, sanitizer report,
# leak, unexpected exception, hang, out-of-memory).
#   bash tools/fuzz.sh [SECONDS] [TARGET...]   build, then run the targets (default: 30 s, all)
#   bash tools/fuzz.sh --build-only            build only (CTest's Fuzz.build)
#   bash tools/fuzz.sh --no-build SECONDS TARGET...   run an existing build (CTest's Fuzz.<target>)
# Everything a run writes stays in build-fuzz/ (corpus copies, logs, crash inputs) or in a scratch
# folder under /dev/shm removed on exit; the seed corpora in the repository never grow.
set -euo pipefail
cd "$(dirname "$0")/.."
source_dir=tests/fuzz
build_dir=build-fuzz
all_targets=()
for source in "$source_dir"/fuzz_*.cpp; do
  name=${source##*/fuzz_}
  all_targets+=("${name%.cpp}")
done

build=1 run=1
case "${1:-}" in
  --build-only) run=0; shift ;;
  --no-build) build=0; shift ;;
esac
seconds=30
if [[ "${1:-}" =~ ^[0-9]+$ ]]; then seconds=$1; shift; fi
targets=("$@")
[ "${#targets[@]}" -gt 0 ] || targets=("${all_targets[@]}")
for target in "${targets[@]}"; do
  [[ " ${all_targets[*]} " == *" $target "* ]] || { echo "fuzz: unknown target '$target', expected one of ${all_targets[*]}" >&2; exit 2; }
done

if [ "$build" -eq 1 ]; then
  if [ ! -f "$build_dir/build.ninja" ] && [ ! -f "$build_dir/Makefile" ]; then
    generator=()
    if command -v ninja >/dev/null; then generator=(-G Ninja); fi
    cmake -S "$source_dir" -B "$build_dir" "${generator[@]}" -DCMAKE_CXX_COMPILER=clang++-14 >/dev/null
  fi
  build_targets=()
  if [ "$run" -eq 1 ]; then
    for target in "${targets[@]}"; do build_targets+=(--target "fuzz_$target"); done
  fi
  if ! cmake --build "$build_dir" -j2 "${build_targets[@]}" >"$build_dir/build.log" 2>&1; then
    cat "$build_dir/build.log" >&2
    echo "fuzz: build failed (log: $build_dir/build.log)" >&2
    exit 1
  fi
fi
[ "$run" -eq 1 ] || exit 0

scratch=$(mktemp -d /dev/shm/fscil-fuzz.XXXXXX 2>/dev/null || mktemp -d)
trap 'rm -rf "$scratch"' EXIT
export FSCIL_FUZZ_SCRATCH=$scratch
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=0:symbolize=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
export LSAN_OPTIONS=suppressions=$PWD/$source_dir/lsan.supp:print_suppressions=0
if [ -x /usr/lib/llvm-14/bin/llvm-symbolizer ]; then export ASAN_SYMBOLIZER_PATH=/usr/lib/llvm-14/bin/llvm-symbolizer; fi

failed=()
for target in "${targets[@]}"; do
  corpus=$build_dir/corpus/$target artifacts=$build_dir/artifacts/$target log=$build_dir/logs/$target.log
  rm -rf "$corpus"
  mkdir -p "$corpus" "$artifacts" "$(dirname "$log")"
  cp "$source_dir/corpus/$target"/* "$corpus"/
  rss_limit=1024 options=()
  [[ "$target" == checkpoint* ]] && rss_limit=2048  # LibTorch alone takes about 400 MB under ASan
  [ "$target" = checkpoint ] && options=(-use_cmp=0)  # no forged digests: see fuzz_checkpoint.cpp
  status=0
  "$build_dir/fuzz_$target" "$corpus" -max_total_time="$seconds" -timeout=10 -rss_limit_mb="$rss_limit" \
    -print_final_stats=1 -artifact_prefix="$artifacts/" "${options[@]}" >"$log" 2>&1 || status=$?
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  coverage=$(grep -oE 'cov: [0-9]+ ft: [0-9]+' "$log" | tail -1 || true)
  files=$(find "$corpus" -type f | wc -l)
  if [ "$status" -eq 0 ]; then
    echo "fuzz $target: ${runs:-?} runs, ${rate:-?} exec/s, ${coverage:-no coverage line}, corpus $files files, no finding"
  else
    input=$(sed -n 's/.*Test unit written to \(.*\)$/\1/p' "$log" | tail -1)
    echo "fuzz $target: FINDING (exit $status) after ${runs:-?} runs: input ${input:-not written}, log $log"
    grep -m1 -E '^(==[0-9]+==ERROR|SUMMARY|.*runtime error|terminate called|==[0-9]+== ERROR)' "$log" | sed 's/^/  /' || true
    failed+=("$target")
  fi
done
if [ "${#failed[@]}" -gt 0 ]; then
  echo "fuzz: findings in ${failed[*]}" >&2
  exit 1
fi
