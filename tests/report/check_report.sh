#!/usr/bin/env bash
# The teaching report in a real browser: `tessera report` writes the page, headless Chromium opens
# it from disk, and the page's own status line must say every image decoded (naturalWidth > 0) and
# no resource failed; Chromium's log must hold no console error. A screenshot stays beside the
# page as the test's artefact (report.png). Usage: check_report.sh TESSERA_BINARY WORK_DIR
set -euo pipefail
tessera=$1
work=$2
rm -rf "$work"
mkdir -p "$work"
"$tessera" report default --out "$work/report" --width 160 --height 90 >"$work/report.log" 2>&1 ||
  { echo "check_report: tessera report failed:"; cat "$work/report.log"; exit 1; }
command -v chromium >/dev/null || { echo "check_report: chromium is not installed (scripts/install-deps.sh installs it)"; exit 1; }
page="file://$(cd "$work/report" && pwd)/index.html"
flags=(--headless --no-sandbox --disable-gpu --hide-scrollbars --user-data-dir="$work/profile" --enable-logging=stderr --v=0)
timeout 120 chromium "${flags[@]}" --virtual-time-budget=10000 --dump-dom "$page" >"$work/dom.html" 2>"$work/chromium.log" ||
  { echo "check_report: chromium failed"; tail -20 "$work/chromium.log"; exit 1; }
timeout 120 chromium "${flags[@]}" --window-size=1400,2000 --screenshot="$work/report/report.png" "$page" \
  >/dev/null 2>>"$work/chromium.log" || { echo "check_report: the screenshot failed"; exit 1; }
status=$(grep -o 'id="status"[^<]*' "$work/dom.html" | sed 's/.*>//')
echo "check_report: $status"
if [[ ! $status =~ ^images\ ([0-9]+)/([0-9]+),\ errors\ 0$ ]] || [[ ${BASH_REMATCH[1]} != "${BASH_REMATCH[2]}" ]] ||
   (( BASH_REMATCH[2] < 20 )); then
  echo "check_report: the page did not load every image without errors (status: '$status')"; exit 1
fi
if grep -E 'CONSOLE|Uncaught' "$work/chromium.log"; then echo "check_report: console messages above"; exit 1; fi
[[ -s $work/report/report.png ]] || { echo "check_report: no screenshot"; exit 1; }
echo "check_report: ok (screenshot $work/report/report.png)"
