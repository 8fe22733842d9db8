#!/usr/bin/env bash
# The protocol whose numbers reports/reference/simtex-mini-smoke.csv stores: every registered
# method on simtex-mini, smoke profile, seeds 1 and 2, 2 threads, on AVX2 kernels.
#   bash tools/reference_protocol.sh check [FSCIL_BENCH]       run it, compare (ctest and CI)
#   bash tools/reference_protocol.sh regenerate [FSCIL_BENCH]  run it, overwrite the stored numbers
set -euo pipefail
mode=${1:-}
root=$(cd "$(dirname "$0")/.." && pwd)
bench=${2:-$root/build/tools/fscil-bench}
reference=$root/reports/reference/simtex-mini-smoke.csv
case $mode in check | regenerate) ;; *) echo "usage: $0 check|regenerate [fscil-bench]" >&2; exit 2 ;; esac

# A short run's accuracies move by up to 10 points when any library's kernels round differently
# (README, "Reference numbers"), so every library is held to AVX2 kernels, whatever else the CPU
# offers; the result files record them. ATen does not check that the CPU has what it is told.
if ! grep -qw avx2 /proc/cpuinfo; then
  echo "$0: the reference numbers are made on AVX2 kernels, and this CPU has no AVX2" >&2
  exit 1
fi
export ATEN_CPU_CAPABILITY=avx2 OPENBLAS_CORETYPE=Haswell ONEDNN_MAX_CPU_ISA=AVX2

out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
"$bench" --methods all --dataset simtex-mini --profile smoke --seeds 1,2 --threads 2 --no-cache --quiet \
  --out "$out" >/dev/null
if [ "$mode" = check ]; then
  "$bench" check --results "$out" --reference "$reference"
else
  "$bench" reference --results "$out" --out "$reference" --tolerance 2
fi
