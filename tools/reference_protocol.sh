#!/usr/bin/env bash
# The protocols whose numbers reports/reference/ stores: every registered method on simtex-mini
# (simtex-mini-smoke.csv) and on sf-instruments-mini (sf-instruments-mini-smoke.csv), seed 1,
# smoke profile, 1 thread, on AVX2 kernels. One seed and one thread each keep the test suite's
# time down (CI's budget is 20 minutes, docs/profiling.md): ctest runs the two data sets as two
# tests beside each other (both, one after the other at 2 threads, held both cores for 173 s on an
# AMD EPYC; one at 1 thread took 107 s), and that another seed changes the numbers is
# Cli.TheSameSeedAndThreadsReproduceAccuraciesExactlyAndAnotherSeedDoesNot's to check.
#   bash tools/reference_protocol.sh check [FSCIL_BENCH [DATASET]]       run it, compare (ctest and CI)
#   bash tools/reference_protocol.sh regenerate [FSCIL_BENCH [DATASET]]  run it, overwrite the stored numbers
# Without DATASET, both.
set -euo pipefail
mode=${1:-}
root=$(cd "$(dirname "$0")/.." && pwd)
bench=${2:-$root/build/tools/fscil-bench}
known=(simtex-mini sf-instruments-mini)
datasets=("${known[@]}")
case $mode in check | regenerate) ;; *) echo "usage: $0 check|regenerate [fscil-bench [dataset]]" >&2; exit 2 ;; esac
if [ -n "${3:-}" ]; then
  [[ " ${known[*]} " == *" $3 "* ]] || { echo "$0: no reference numbers for '$3', expected one of ${known[*]}" >&2; exit 2; }
  datasets=("$3")
fi

# A short run's accuracies move by up to 10 points when any library's kernels round differently
# (README, "Reference numbers"), so every library is held to AVX2 kernels, whatever else the CPU
# offers; the result files record them. ATen does not check that the CPU has what it is told.
if ! grep -qw avx2 /proc/cpuinfo; then
  echo "$0: the reference numbers are made on AVX2 kernels, and this CPU has no AVX2" >&2
  exit 1
fi
export ATEN_CPU_CAPABILITY=avx2 OPENBLAS_CORETYPE=Haswell ONEDNN_MAX_CPU_ISA=AVX2

scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
status=0
for dataset in "${datasets[@]}"; do
  reference=$root/reports/reference/$dataset-smoke.csv
  out=$scratch/$dataset
  "$bench" --methods all --dataset "$dataset" --profile smoke --seeds 1 --threads 1 --no-cache \
    --quiet --out "$out" >/dev/null
  if [ "$mode" = check ]; then
    "$bench" check --results "$out" --reference "$reference" || status=1
  else
    "$bench" reference --results "$out" --out "$reference" --tolerance 2
  fi
done
exit $status
