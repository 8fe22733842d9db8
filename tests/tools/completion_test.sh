#!/usr/bin/env bash
# The bash completion names every option and subcommand of `fscil-bench --help-all`, and completes
# option names, methods and subcommand options when sourced.
set -euo pipefail
bench="$1"
completion="$2"
fail() {
  echo "FAIL: $*" >&2
  exit 1
}
help="$("$bench" --help-all)"
missing=()
for option in $(echo "$help" | grep -oE '^ *(-h,)?--[a-z][a-z-]*' | sed 's/.*--/--/' | sort -u); do
  grep -qE -- "(^|[ \"])$option([ \"]|$)" "$completion" || missing+=("$option")
done
for subcommand in $(echo "$help" | sed -n '/^Subcommands:/,$p' | grep -oE '^[a-z][a-z-]*$'); do
  grep -qE -- "(^|[ \"])$subcommand([ \"]|$)" "$completion" || missing+=("$subcommand")
done
[ "${#missing[@]}" -eq 0 ] || fail "$completion does not name: ${missing[*]}"

complete_line() {  # the completions of the words given, the last one being completed
  # shellcheck disable=SC1090
  source "$completion"
  COMP_WORDS=("$bench" "$@")
  COMP_CWORD=$#
  COMPREPLY=()
  _fscil_bench
  echo "${COMPREPLY[*]}"
}
[ "$(complete_line --prof)" = "--profile" ] || fail "--prof completes to '$(complete_line --prof)'"
[ "$(complete_line --methods proto)" = "prototype" ] || fail "--methods proto completes to '$(complete_line --methods proto)'"
[ "$(complete_line slurm --max-p)" = "--max-parallel" ] || fail "slurm --max-p completes to '$(complete_line slurm --max-p)'"
[ "$(complete_line reproduce embe)" = "embedding" ] || fail "reproduce embe completes to '$(complete_line reproduce embe)'"
[ "$(complete_line --selection test)" = "test-oracle" ] || fail "--selection test completes to '$(complete_line --selection test)'"
echo "the completion names all $(echo "$help" | grep -oE '^ *(-h,)?--[a-z][a-z-]*' | sort -u | wc -l) options and completes them"
