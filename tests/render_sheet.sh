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
#   - opens a copy of the page with a small script at its end that asks the
#     browser's own SVG DOM, for each plot series, how many points its
#     polyline holds and how many marker shapes it built, and whether it
#     was laid out with a size (--dump-dom prints the answer): the commanded
#     and the actual series must each have 400, as the page axterm wrote.
# Exit 0 when every check passed, 1 when one failed, 77 (skipped) when no
# browser is on PATH. tests/render_sheet.rs runs it in the test suite;
# .ci/run installs Chromium and sets AXTERM_REQUIRE_BROWSER=1 so that a
# missing browser fails there. axterm is $AXTERM, else target/debug/axterm
# (cargo build first).
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
# The rest keep a headless Chromium off the network (a closed network makes
# it hang on its own background connections) and start it from a fresh,
# empty profile each time.
profile=$(mktemp -d)
trap 'rm -rf "$profile"' EXIT
flags="--headless --no-sandbox --disable-gpu --disable-quic --no-first-run \
 --disable-background-networking --disable-component-update --disable-sync \
 --hide-scrollbars --user-data-dir=$profile"

# shellcheck disable=SC2086
"$browser" $flags --print-to-pdf="$out/sheet.pdf" --no-pdf-header-footer "$url" >/dev/null 2>&1 || true
# A4 at 150 dpi: 1240 x 1754.
# shellcheck disable=SC2086
"$browser" $flags --window-size=1240,1754 --screenshot="$out/sheet.png" "$url" >/dev/null 2>&1 || true

[ "$(head -c 5 "$out/sheet.pdf" 2>/dev/null)" = "%PDF-" ] || say_fail "no PDF was printed ($out/sheet.pdf)"
[ "$(head -c 4 "$out/sheet.png" 2>/dev/null | tail -c 3)" = "PNG" ] || say_fail "no PNG screenshot ($out/sheet.png)"

# What the browser made of the plots, asked of its own SVG DOM: a copy of
# the page (the sheet itself has no script and stays so) with a script at
# its end that, for each series, writes the number of points the browser
# parsed into the polyline (SVGPointList.numberOfItems), the number of
# marker shapes it built as SVG elements, and whether the series was laid
# out with a size (getBBox). --dump-dom prints the DOM after the script ran.
probe=$out/sheet-probe.html
sed 's|</body>|<script>\
var out = [];\
document.querySelectorAll("svg.plot g.series").forEach(function (g) {\
  var line = g.querySelector("polyline");\
  var markers = 0;\
  g.querySelectorAll(".point").forEach(function (m) {\
    if (m instanceof SVGGeometryElement) { markers++; }\
  });\
  var box = g.getBBox();\
  out.push("[series " + g.getAttribute("data-name") + ": polyline=" + (line ? line.points.numberOfItems : 0) + " markers=" + markers + " laid-out=" + (box.width > 0 \&\& box.height > 0) + "]");\
});\
var pre = document.createElement("pre");\
pre.id = "render-check";\
pre.textContent = out.join("\\n");\
document.body.appendChild(pre);\
</script>\
</body>|' "$sheet" >"$probe"
# shellcheck disable=SC2086
"$browser" $flags --dump-dom "file://$probe" >"$out/dom.html" 2>/dev/null || true

# The markers (class="point") of the series named $2 in the page $1 as
# axterm wrote it: from its <g data-name=…> to the </g> that closes it.
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

# The browser's count for series $1, from its "[series NAME: polyline=N
# markers=M laid-out=B]": what is after the colon.
browser_said() {
    grep -o "\\[series $1: [^]]*\\]" "$out/dom.html" | head -n 1 | sed 's/^[^:]*: //; s/]$//'
}

# The example's :tune-step records 400 samples: each series has 400 points
# in the page axterm wrote, and the browser's SVG DOM must hold as many in
# the series' polyline and as many markers, laid out with a size.
grep -q 'id="render-check"' "$out/dom.html" || say_fail "the browser ran no check of the page ($out/dom.html)"
for series in commanded actual; do
    written=$(points "$sheet" "$series")
    [ "$written" = 400 ] || say_fail "the $series series has $written points in $sheet, not 400"
    said=$(browser_said "$series")
    want="polyline=$written markers=$written laid-out=true"
    [ "$said" = "$want" ] || say_fail "the $series series in the browser's SVG DOM: '${said:-nothing}', not '$want'"
done

if [ "$fail" = 0 ]; then
    echo "render_sheet: ok: $out/sheet.pdf, $out/sheet.png; 400 points a series in the browser's SVG DOM"
fi
exit "$fail"
