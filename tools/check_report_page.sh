#!/usr/bin/env bash
# Opens a report page (DIR/index.html, written by write_report_page) in headless Chromium and checks
# that every figure loads and renders: prints one line per figure with its natural and shown size
# and the share of its pixels that are drawn, and exits 1 when
#   - a figure does not load (missing file, invalid SVG: natural size 0x0) or draws nothing,
#   - the page shows fewer or more figures than DIR holds (figures/*.svg outside results/,
#     checkpoints/ and hidden folders, as the page lists them),
#   - a table is cut: shown in a scroll box narrower than the table where the page, 1400 px wide,
#     has room for it whole,
#   - the browser logs any console message for the page. The page has no script, so any message
#     is an error; Chromium prints every console level as INFO on stderr, so levels cannot be told
#     apart there anyway.
# Chromium missing is a failure too, never a skip. Usage: bash tools/check_report_page.sh DIR/index.html
set -euo pipefail

fail() {
  echo "check_report_page: $*" >&2
  exit 1
}

[ $# -eq 1 ] || fail "usage: bash tools/check_report_page.sh DIR/index.html"
[ -f "$1" ] || fail "no such page: $1"
browser=$(command -v chromium || true)
[ -n "$browser" ] || fail "chromium is not installed (bash tools/bootstrap.sh installs Debian's chromium package)"

folder=$(cd "$(dirname "$1")" && pwd -P)
page="$folder/$(basename "$1")"

# A file URL of an absolute path: bytes outside [A-Za-z0-9/._~-] percent-encoded.
file_url() {
  local path=$1 url="file://" i c
  local LC_ALL=C
  for ((i = 0; i < ${#path}; i++)); do
    c=${path:i:1}
    case "$c" in
      [A-Za-z0-9/._~-]) url+="$c" ;;
      *) url+=$(printf '%%%02X' "'$c") ;;
    esac
  done
  printf '%s' "$url"
}

expected=$(find "$folder" -mindepth 1 -type d \( -name checkpoints -o -name results -o -name '.*' \) -prune \
  -o -type f -path '*/figures/*.svg' ! -name '.*' -print | grep -c '/figures/[^/]*\.svg$' || true)

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# The checker loads the page in an iframe (same origin for file URLs under
# --allow-file-access-from-files), waits for its load event, which comes after every image has
# loaded or failed, and writes its verdict into its own DOM for --dump-dom. Drawing each image on
# a canvas tells an SVG that loads but draws nothing from one that renders.
cat > "$work/check.html" <<EOF
<!DOCTYPE html>
<html><head><meta charset="utf-8"><title>report page check</title></head>
<body>
<pre id="verdict">pending</pre>
<iframe id="page" src="$(file_url "$page")" width="1400" height="1000"></iframe>
<script>
const frame = document.getElementById('page');
frame.addEventListener('load', () => {
  const lines = ['VERDICT-BEGIN'];
  let document_of_page = null;
  try { document_of_page = frame.contentDocument; } catch (error) { lines.push('ERROR cannot read the page: ' + error); }
  if (document_of_page === null) lines.push('ERROR cannot read the page (file access from files refused)');
  const images = document_of_page === null ? [] : Array.from(document_of_page.images);
  for (const image of images) {
    const source = image.getAttribute('src');
    const shown = image.getBoundingClientRect();
    const size = image.naturalWidth + 'x' + image.naturalHeight;
    const shown_size = Math.round(shown.width) + 'x' + Math.round(shown.height);
    if (!image.complete || image.naturalWidth === 0 || image.naturalHeight === 0) {
      lines.push('FAIL ' + source + ' does not load (natural size ' + size + ')');
      continue;
    }
    let drawn = 0;
    try {
      const canvas = document.createElement('canvas');
      canvas.width = image.naturalWidth;
      canvas.height = image.naturalHeight;
      const context = canvas.getContext('2d');
      context.drawImage(image, 0, 0);
      const pixels = context.getImageData(0, 0, canvas.width, canvas.height).data;
      for (let i = 0; i < pixels.length; i += 4) {
        if (pixels[i + 3] > 0 && (pixels[i] < 250 || pixels[i + 1] < 250 || pixels[i + 2] < 250)) ++drawn;
      }
    } catch (error) {
      lines.push('FAIL ' + source + ' cannot be drawn on a canvas: ' + error);
      continue;
    }
    const share = 100 * drawn / (image.naturalWidth * image.naturalHeight);
    if (drawn === 0 || shown.width === 0 || shown.height === 0) {
      lines.push('FAIL ' + source + ' draws nothing (natural size ' + size + ', shown ' + shown_size + ')');
    } else {
      lines.push('OK ' + source + ' natural ' + size + ' shown ' + shown_size + ' drawn ' + share.toFixed(1) + '%');
    }
  }
  // A table in a scroll box narrower than the table while the page has room for it is cut for
  // no reason: the reader scrolls to see columns the window could show.
  const tables = document_of_page === null ? [] : Array.from(document_of_page.querySelectorAll('div.table'));
  const room = document_of_page === null ? 0 : document_of_page.documentElement.clientWidth - 40;
  for (const box of tables) {
    const name = box.previousElementSibling === null ? 'a table' : box.previousElementSibling.textContent;
    if (box.scrollWidth > box.clientWidth + 1 && box.scrollWidth <= room) {
      lines.push('FAIL ' + name + ' is cut: ' + box.scrollWidth + ' px wide in a ' + box.clientWidth + ' px box, ' +
                 room + ' px of page');
    }
  }
  lines.push('IMAGES ' + images.length);
  lines.push('VERDICT-END');
  document.getElementById('verdict').textContent = lines.join('\n');
});
</script>
</body></html>
EOF

# --no-sandbox: Chromium's sandbox does not start as root or in most containers, and the page is a
# local file this harness wrote.
status=0
timeout 90 "$browser" --headless --no-sandbox --disable-gpu --no-first-run --user-data-dir="$work/profile" \
  --allow-file-access-from-files --window-size=1440,1000 --virtual-time-budget=5000 \
  --enable-logging=stderr --v=0 --dump-dom "$(file_url "$work/check.html")" \
  > "$work/dom.html" 2> "$work/browser.log" || status=$?
[ "$status" -eq 0 ] || fail "chromium exited with status $status; its last lines: $(tail -n 3 "$work/browser.log" | tr '\n' ' ')"

verdict=$(sed -n '/id="verdict">VERDICT-BEGIN/,/VERDICT-END<\/pre>/p' "$work/dom.html" | sed -e 's/&lt;/</g' -e 's/&gt;/>/g' -e 's/&quot;/"/g' \
  -e "s/&#39;/'/g" -e 's/&amp;/\&/g' | grep -v 'VERDICT-' || true)
[ -n "$verdict" ] || fail "the checker did not finish: the page did not load within the time budget"

failed=0
while IFS= read -r line; do
  case "$line" in
    IMAGES*) shown=${line#IMAGES } ;;
    OK*) echo "$line" ;;
    *) echo "$line"; failed=1 ;;
  esac
done <<< "$verdict"

if [ "${shown:-0}" != "$expected" ]; then
  echo "FAIL the page shows ${shown:-0} figures, $folder holds $expected"
  failed=1
fi
while IFS= read -r message; do
  echo "FAIL console: $message"
  failed=1
done < <(grep -F ':CONSOLE' "$work/browser.log" | sed 's/^\[[^]]*\] //' || true)

if [ "$failed" -ne 0 ]; then
  echo "check_report_page: $page: FAILED" >&2
  exit 1
fi
echo "check_report_page: $page: all $expected figures render"
