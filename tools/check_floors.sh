#!/usr/bin/env bash
# Checks that every include arrow between the source floors points down (docs/architecture.md,
# "Floors"): a file under FLOOR/ may include "OTHER/..." only where OTHER is listed below for FLOOR.
#   bash tools/check_floors.sh [ROOT]    exits 1 naming each upward or sideways include
set -euo pipefail
root=${1:-$(cd "$(dirname "$0")/.." && pwd)}

declare -A may_include=(
  [core]=""
  [metrics]="core"
  [datasets]="core"
  [methods]="core metrics datasets"
  [protocols]="core metrics datasets methods"
  [reports]="core metrics datasets"
  [tools]="core metrics datasets methods protocols reports"
)

status=0
checked=0
for floor in "${!may_include[@]}"; do
  [ -d "$root/$floor" ] || { echo "check_floors: $root/$floor: expected the floor's folder" >&2; exit 1; }
  while IFS= read -r -d '' file; do
    checked=$((checked + 1))
    line_number=0
    while IFS= read -r line; do
      line_number=$((line_number + 1))
      [[ $line =~ ^[[:space:]]*#[[:space:]]*include[[:space:]]*\"([a-z_]+)/ ]] || continue
      target=${BASH_REMATCH[1]}
      [ "$target" = "$floor" ] && continue
      [ -n "${may_include[$target]+known}" ] || continue  # not a floor (a generated header's folder)
      if [[ " ${may_include[$floor]} " != *" $target "* ]]; then
        echo "${file#"$root"/}:$line_number: $floor/ includes $target/ (${floor}/ may include: ${may_include[$floor]:-nothing})"
        status=1
      fi
    done < "$file"
  done < <(find "$root/$floor" \( -name '*.h' -o -name '*.cpp' \) -print0)
done
[ "$status" -eq 0 ] && echo "check_floors: $checked files, every include points down"
exit "$status"
