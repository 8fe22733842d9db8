#!/usr/bin/env bash
# The Slurm scale-out against a real Slurm (tools/slurm_local.sh), in steps that ctest runs as
# fixtures and cases (tests/CMakeLists.txt, label slurm):
#   slurm_test.sh FSCIL_BENCH WORK start       the single-node cluster
#   slurm_test.sh FSCIL_BENCH WORK local       the command run plainly, the numbers to match
#   slurm_test.sh FSCIL_BENCH WORK array       array + merge job: summary.csv equals the local one
#   slurm_test.sh FSCIL_BENCH WORK preempted   one task sent SIGTERM mid-way, --missing-only
#                                              finishes it from its checkpoint: the same numbers
#   slurm_test.sh FSCIL_BENCH WORK cells       run-cells --jobs 2, without Slurm: the same numbers
#   slurm_test.sh FSCIL_BENCH WORK shared      run-cells --jobs 2 of two cells sharing a stage: it is
#                                              trained once, and the numbers are a plain run's
#   slurm_test.sh FSCIL_BENCH WORK stop        the cluster down
set -euo pipefail
bench="$1"
work="$2"
step="$3"
root="$(cd "$(dirname "$0")/../.." && pwd)"
export FSCIL_SLURM_DIR="$work/cluster"
export FSCIL_SLURM_PORT="${FSCIL_SLURM_PORT:-16817}"  # clear of a real Slurm's 6817
export SLURM_CONF="$FSCIL_SLURM_DIR/slurm.conf"
export PATH="$PATH:/usr/sbin"
# 2 methods x 1 seed: 2 cells, run 2 at a time. cop-fscil's sessions take seconds, so a task can be
# stopped between its checkpoints. No stage cache: every task trains its base.
command=(--methods prototype,cop-fscil --dataset simtex-mini --profile smoke --seeds 1 --cache-dir "$work/cache"
         --no-stage-cache)

fail() {
  echo "FAIL: $*" >&2
  exit 1
}

job_state() { scontrol -o show job "$1" 2>/dev/null | grep -o 'JobState=[A-Z_]*' | sort -u | cut -d= -f2 | paste -sd, -; }

# Waits until every task of job $1 has ended; prints how long it took.
wait_for_job() {
  local job="$1" start=$SECONDS state
  while :; do
    state="$(job_state "$job")"
    [ -n "$state" ] || fail "job $job: slurmctld knows no such job"
    if ! echo "$state" | grep -qE 'PENDING|RUNNING|CONFIGURING|COMPLETING|REQUEUED|SUSPENDED'; then break; fi
    [ $((SECONDS - start)) -lt 400 ] || fail "job $job still $state after 400 s"
    sleep 1
  done
  echo "job $job ended ($state) after $((SECONDS - start)) s"
}

submit() {  # fscil-bench slurm ... --submit; prints its output, sets array_job and merge_job
  local output
  output="$("$bench" slurm "${command[@]}" --out "$1" --cpus-per-task 1 --submit "${@:2}")" ||
    fail "fscil-bench slurm failed: $output"
  echo "$output"
  array_job="$(echo "$output" | sed -n 's/^Submitted array job \([0-9]*\) and merge job \([0-9]*\)$/\1/p')"
  merge_job="$(echo "$output" | sed -n 's/^Submitted array job \([0-9]*\) and merge job \([0-9]*\)$/\2/p')"
  [ -n "$array_job" ] && [ -n "$merge_job" ] || fail "no job ids in: $output"
}

same_summary() {  # the merged tables of $1 hold the local run's numbers, value for value
  [ -f "$1/summary.csv" ] || fail "$1/summary.csv: the merge job wrote no tables (log: $1/cell-logs/merge.log)"
  if ! cmp -s "$work/local/summary.csv" "$1/summary.csv"; then
    diff "$work/local/summary.csv" "$1/summary.csv" >&2 || true
    fail "$1/summary.csv differs from the same command run locally"
  fi
  echo "$1/summary.csv equals the local run's, value for value ($(($(wc -l <"$1/summary.csv") - 1)) methods)"
}

case "$step" in
  start)
    mkdir -p "$work"
    bash "$root/tools/slurm_local.sh" start
    ;;
  stop)
    bash "$root/tools/slurm_local.sh" stop
    ;;
  local)
    rm -rf "$work/local"
    start=$SECONDS
    "$bench" "${command[@]}" --threads 1 --out "$work/local" >/dev/null 2>&1
    echo "local run: $((SECONDS - start)) s"
    cat "$work/local/summary.csv"
    ;;
  array)
    out="$work/array"
    rm -rf "$out"
    "$bench" plan "${command[@]}" --out "$out"
    start=$SECONDS
    submit "$out"
    echo "--- $out/slurm/array.sbatch"; cat "$out/slurm/array.sbatch"
    echo "--- $out/slurm/merge.sbatch"; cat "$out/slurm/merge.sbatch"
    wait_for_job "$array_job"
    wait_for_job "$merge_job"
    echo "array and merge: $((SECONDS - start)) s"
    for task in 0 1; do
      [ "$(job_state "${array_job}_$task")" = COMPLETED ] || fail "task $task: $(job_state "${array_job}_$task") (log: $out/cell-logs/cell-$task.log)"
    done
    [ "$(job_state "$merge_job")" = COMPLETED ] || fail "merge job: $(job_state "$merge_job")"
    same_summary "$out"
    ;;
  preempted)
    out="$work/preempted"
    rm -rf "$out"
    start=$SECONDS
    submit "$out"
    # Cell 1 is cop-fscil, seed 1: stopped once its first checkpoint (after the base session) exists.
    checkpoint="$out/checkpoints/cop-fscil__simtex-mini__seed1.ckpt"
    while [ ! -f "$checkpoint" ]; do
      [ $((SECONDS - start)) -lt 600 ] || fail "$checkpoint never appeared"
      sleep 0.05
    done
    scancel --batch --signal=TERM "${array_job}_1"
    echo "sent SIGTERM to task ${array_job}_1 after $((SECONDS - start)) s"
    wait_for_job "$array_job"
    wait_for_job "$merge_job"
    log="$out/cell-logs/cell-1.log"
    grep -q "stopped by SIGTERM" "$log" || fail "$log: the task did not report the stop: $(tail -n 3 "$log")"
    [ ! -f "$out/results/cop-fscil__simtex-mini__seed1.json" ] || fail "the stopped task finished anyway (sent too late)"
    [ -f "$checkpoint" ] || fail "$checkpoint: the stopped task left no checkpoint"
    echo "task 1 stopped, its checkpoint kept: $(grep "stopped by SIGTERM" "$log")"
    [ "$(job_state "$merge_job")" = FAILED ] || fail "merge job $merge_job: $(job_state "$merge_job") with a cell missing"
    grep -q "^    1  cop-fscil " "$out/cell-logs/merge.log" || fail "the merge job's log does not name the missing cell 1"
    submit "$out" --missing-only
    grep -q -- "--array=1$" "$out/slurm/array.sbatch" || fail "--missing-only did not submit exactly cell 1: $(grep -- --array "$out/slurm/array.sbatch")"
    wait_for_job "$array_job"
    wait_for_job "$merge_job"
    grep -q "continuing after session" "$log" || fail "$log: the resubmitted task did not continue from the checkpoint"
    grep "continuing after session" "$log"
    [ ! -f "$checkpoint" ] || fail "$checkpoint: still there after the run finished"
    same_summary "$out"
    ;;
  cells)
    # The command's 2 cells, two at a time, against the local run.
    out="$work/cells"
    rm -rf "$out"
    start=$SECONDS
    "$bench" run-cells --jobs 2 --threads 2 "${command[@]}" --out "$out" >/dev/null
    echo "run-cells --jobs 2 (1 thread per cell): $((SECONDS - start)) s"
    [ "$(ls "$out/cell-logs" | wc -l)" -eq 2 ] || fail "$out/cell-logs: expected one log per cell, found $(ls "$out/cell-logs")"
    same_summary "$out"
    ;;
  shared)
    # pits-sc and cop-fscil/cpi are two cells that share pits-sc's pretraining; started together on
    # one stage cache, one trains it and the other waits for it and takes it over.
    shared=(--methods pits-sc,cop-fscil/cpi --dataset simtex-mini --profile smoke --seeds 1 --cache-dir "$work/cache")
    out="$work/shared"
    rm -rf "$out" "$work/shared-local" "$work/cache/stages"
    "$bench" "${shared[@]}" --no-stage-cache --threads 1 --out "$work/shared-local" >/dev/null 2>&1
    start=$SECONDS
    "$bench" run-cells --jobs 2 --threads 2 "${shared[@]}" --out "$out" >/dev/null
    echo "run-cells --jobs 2 (1 thread per cell): $((SECONDS - start)) s"
    taken="$(grep -l "pits-sc pretraining from the stage cache" "$out"/cell-logs/*.log | wc -l)"
    [ "$taken" -eq 1 ] || fail "expected one cell to take pits-sc's pretraining over, $taken did: $(grep -h "pretraining\|waiting" "$out"/cell-logs/*.log)"
    grep -h "waiting for a stage\|pretraining from the stage cache" "$out"/cell-logs/*.log
    if ! cmp -s "$work/shared-local/summary.csv" "$out/summary.csv"; then
      diff "$work/shared-local/summary.csv" "$out/summary.csv" >&2 || true
      fail "$out/summary.csv differs from the same command run plainly"
    fi
    echo "$out/summary.csv equals the plain run's, value for value"
    ;;
  *)
    fail "unknown step $step"
    ;;
esac
