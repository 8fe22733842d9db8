#!/usr/bin/env bash
# A method compiled outside the tree joins the registry and the command line: the example is built
# against the package the Install test put in PREFIX, listed, and run beside a built-in method
# through the smoke protocol; a second run takes its base from the stage cache, which only its
# default save_state/restore_state can give, and must end with the same numbers.
#   out_of_tree_test.sh SOURCE_DIR PREFIX WORK
set -euo pipefail
source_dir="$1"
prefix="$2"
work="$3"
fail() {
  echo "FAIL: $*" >&2
  exit 1
}
rm -rf "$work"
mkdir -p "$work"
launcher=()
# Paths below the source tree hashed as relative ones (as the main build does): a CI clone in
# another folder reuses the example's object an earlier clone compiled.
if command -v ccache >/dev/null; then launcher=("-DCMAKE_CXX_COMPILER_LAUNCHER=env;CCACHE_BASEDIR=$source_dir;ccache"); fi
cmake -S "$source_dir/examples/out_of_tree_method" -B "$work/build" -DCMAKE_PREFIX_PATH="$prefix" "${launcher[@]}" \
  >"$work/configure.log" 2>&1 || fail "configure against $prefix: $(grep -m 3 -i -A 2 error "$work/configure.log")"
cmake --build "$work/build" -j 2 >"$work/build.log" 2>&1 || fail "build: $(grep -m 3 -i -A 2 error "$work/build.log")"
bench="$work/build/my-bench"
echo "built $bench against $prefix"

# Read whole, not piped to grep -q: grep leaves at its first match, and a listing written in
# several writes then fails the next one (EPIPE), which pipefail makes this line's failure.
listed="$("$bench" list)"
grep -q '^  small-cnn-ncm ' <<<"$listed" || fail "my-bench list does not name small-cnn-ncm"
"$bench" --version | grep -qx "  data       $prefix/share/fscil-bench" ||
  fail "my-bench reads its data from another folder than the package's: $("$bench" --version)"
"$bench" --methods no-such-method --dataset simtex-mini 2>"$work/unknown.err" && fail "an unknown method ran"
grep -q "one of prototype, .*, small-cnn-ncm\b" "$work/unknown.err" || fail "unknown-method error: $(cat "$work/unknown.err")"

run() {  # OUT METHODS: the smoke protocol, one seed, one thread, segments and bases cached in WORK/cache
  "$bench" --methods "$2" --dataset simtex-mini --profile smoke --seeds 1 --threads 1 --cache-dir "$work/cache" \
    --out "$work/$1" >"$work/$1.log" 2>&1 || fail "$1: $(tail -n 3 "$work/$1.log")"
}
run first small-cnn-ncm,prototype
summary="$work/first/summary.csv"
grep -q '^small-cnn-ncm,simtex-mini,' "$summary" || fail "$summary has no small-cnn-ncm row"
grep -q '^prototype,simtex-mini,' "$summary" || fail "$summary has no prototype row"
# Above chance (10 base classes of simtex-mini: 10%) in the base session.
awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) column[$i] = i } $1 == "small-cnn-ncm" { exit !($column["acc_0"] > 20) }' \
  "$summary" || fail "small-cnn-ncm learnt nothing: $(grep small-cnn-ncm "$summary")"
# Traced cost against the hand count on simtex-mini's 5 x 64 x 24 maps, the model after the last
# session: conv 5->32 (49 152 outputs x 45) + norm 49 152 + conv 32->32 stride 2 (12 288 x 288) +
# norm 12 288 + global average 12 288 + 20 class means x 32 = 5 825 152 MACs, 11.65 MFLOPs.
awk -F, '$1 == "small-cnn-ncm" { exit !($4 == "11.7") }' "$work/first/costs.csv" ||
  fail "small-cnn-ncm's traced cost is not the hand count's 11.7 MFLOPs: $(grep small-cnn-ncm "$work/first/costs.csv")"
echo "first run: $(grep '^small-cnn-ncm,' "$summary" | cut -d, -f1,6-11)"

run second small-cnn-ncm
grep -q "base session from the stage cache" "$work/second.log" || fail "the base was not restored from the stage cache"
cmp -s <(grep '^small-cnn-ncm,' "$summary") <(grep '^small-cnn-ncm,' "$work/second/summary.csv") ||
  fail "restored from the stage cache, the run ended with other numbers"
# The cost columns (FLOPs, parameters, those trained in sessions), not the timings.
costs() { awk -F, '$1 == "small-cnn-ncm" { print $4, $5, $6 }' "$1"; }
[ "$(costs "$work/first/costs.csv")" = "$(costs "$work/second/costs.csv")" ] ||
  fail "restored from the stage cache, the costs differ: $(costs "$work/first/costs.csv") / $(costs "$work/second/costs.csv")"
echo "a base restored from the stage cache gives the same numbers and costs ($(costs "$work/first/costs.csv"))"
