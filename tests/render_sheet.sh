#!/bin/sh
# Render a commissioning sheet in a real browser, headless, and check what
# the browser made of it (docs/sheet.md, "In a browser").
#
#   tests/render_sheet.sh [OUTPUT_DIR]
#
# It runs the MCCL commissioning example on the simulator (its sheet has a
# step-response plot of 400 samples a series), then with the first of
# chromium, chromium-browser, google-chrome, google-chrome-stable on PATH
# (or $BROWSER_BIN):
#   - prints the page to PDF (sheet.pdf) and takes a screenshot at A4's
#     proportions (sheet.png), each checked to be a PDF or PNG file;
#   - dumps the DOM the browser built (--dump-dom) and counts the markers of
#     each plot series there: the commanded and the actual series must each
#     have as many points as the sheet's JSON says (400).
# Exit 0 when every check passed, 1 when one failed, 77 (skipped) when no
# browser is on PATH. CI does not install a browser; run it by hand where
# one is. axterm is $AXTERM, else target/debug/axterm (cargo build first).
set -eu

here=$(cd "$(dirname "$0")/.." && pwd)
axterm=${AXTERM:-$here/target/debug/axterm}
browser=${BROWSER_BIN:-}
if [ -z "$browser" ]; then
    for name in chromium chromium-browser google-chrome google-chrome-stable; do
        if command -v "$name" >/dev/null 2>&1; then
            browser=$name
            break
        fi
    done
fi
if [ -z "$browser" ]; then
    echo "render_sheet: skipped: no chromium, chromium-browser or google-chrome on PATH" >&2
    exit 77
fi
if [ ! -x "$axterm" ]; then
    echo "render_sheet: $axterm is not there: cargo build first, or set AXTERM" >&2
    exit 1
fi

out=${1:-$(mktemp -d)}
mkdir -p "$out"
sheet=$out/sheet.html
json=$out/sheet.json
fail=0
say_fail() {
    echo "render_sheet: FAIL: $*" >&2
    fail=1
}

"$axterm" run --sim mccl --yes "$here/examples/mccl/commission.txt" \
    --report "$sheet" --report-json "$json" --force >/dev/null 2>&1 || {
    echo "render_sheet: the example run failed (see: $axterm run --sim mccl --yes examples/mccl/commission.txt)" >&2
    exit 1
}
url="file://$sheet"
# --no-sandbox: a container's root has no user namespace for the sandbox.
flags="--headless --disable-gpu --no-sandbox --hide-scrollbars"

# shellcheck disable=SC2086
"$browser" $flags --print-to-pdf="$out/sheet.pdf" --no-pdf-header-footer "$url" >/dev/null 2>&1 || true
# A4 at 150 dpi: 1240 x 1754.
# shellcheck disable=SC2086
"$browser" $flags --window-size=1240,1754 --screenshot="$out/sheet.png" "$url" >/dev/null 2>&1 || true
# shellcheck disable=SC2086
"$browser" $flags --dump-dom "$url" >"$out/dom.html" 2>/dev/null || true

[ "$(head -c 5 "$out/sheet.pdf" 2>/dev/null)" = "%PDF-" ] || say_fail "no PDF was printed ($out/sheet.pdf)"
[ "$(head -c 4 "$out/sheet.png" 2>/dev/null | tail -c 3)" = "PNG" ] || say_fail "no PNG screenshot ($out/sheet.png)"

# The markers (class="point") of the series named $2 in the page $1: from
# its <g data-name=…> to the </g> that closes it.
points() {
    awk -v name="data-name=\"$2\"" '
        index($0, name) { inside = 1 }
        inside {
            line = $0
            while ((i = index(line, "class=\"point\"")) > 0) {
                count++
                line = substr(line, i + 1)
            }
            if (index($0, "</g>")) { inside = 0 }
        }
        END { print count + 0 }
    ' "$1"
}

# The example's :tune-step records 400 samples: each series has 400 points
# in the page axterm wrote, and must have as many in the browser's DOM.
for series in commanded actual; do
    written=$(points "$sheet" "$series")
    got=$(points "$out/dom.html" "$series")
    [ "$written" = 400 ] || say_fail "the $series series has $written points in $sheet, not 400"
    [ "$got" = "$written" ] || say_fail "the $series series has $got points in the browser's DOM, $written in the page"
done
grep -q '<svg' "$out/dom.html" || say_fail "no <svg> in the browser's DOM ($out/dom.html)"

if [ "$fail" = 0 ]; then
    echo "render_sheet: ok: $out/sheet.pdf, $out/sheet.png; 400 points a series in the DOM"
fi
exit "$fail"
