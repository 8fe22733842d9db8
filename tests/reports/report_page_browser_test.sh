#!/usr/bin/env bash
# The report page in headless Chromium (tools/check_report_page.sh), on a folder written by
# fscil_report_page_fixture.
#   good:   every figure of the page must render, and the check pass.
#   broken: the same folder with one figure's SVG cut short, one emptied to a blank drawing, one
#           deleted after the page was written, a console error added to the page and the page made
#           narrower than its widest table: the check
#           must fail and name each of them, so it is known to catch what it is there for.
# Usage: report_page_browser_test.sh FIXTURE CHECK_SCRIPT WORK_DIR good|broken
set -euo pipefail
fixture=$1 check=$2 work=$3 mode=$4

rm -rf "$work"
"$fixture" "$work"

if [ "$mode" = good ]; then
  bash "$check" "$work/index.html"
  exit
fi

printf '<?xml version="1.0"?>\n<svg xmlns="http://www.w3.org/2000/svg" width="640" height="400"><rect' \
  > "$work/figures/cost_per_method.svg"
printf '<svg xmlns="http://www.w3.org/2000/svg" version="1.1" width="640" height="400"><rect width="640" height="400" fill="#ffffff"/></svg>\n' \
  > "$work/figures/prototypes_on_unit_circle.svg"
rm "$work/shot-5/figures/accuracy_per_session.svg"
sed -i 's|</body>|<script>console.error("deliberate error")</script></body>|' "$work/index.html"
sed -i 's|max-width:100rem|max-width:50rem|' "$work/index.html"  # the page narrower than the sessions table

status=0
output=$(bash "$check" "$work/index.html" 2>&1) || status=$?
echo "$output"
[ "$status" -ne 0 ] || { echo "the check passed a broken page"; exit 1; }
for expected in "FAIL figures/cost_per_method.svg does not load" \
                "FAIL figures/prototypes_on_unit_circle.svg draws nothing" \
                "FAIL shot-5/figures/accuracy_per_session.svg does not load" \
                "FAIL the page shows 4 figures" \
                "FAIL console: \"deliberate error\"" \
                "FAIL sessions.csv is cut" \
                "OK figures/accuracy_per_session.svg"; do
  grep -qF "$expected" <<< "$output" || { echo "missing from the check's output: $expected"; exit 1; }
done
echo "the check fails the broken page and names every broken figure"
