#!/usr/bin/env bash
# Checks and renders the page of `aggkit validate` (DIR/report.html) as a browser shows it: first every image
# and local link the page references must exist (Python's html.parser on the page, paths relative to it),
# then headless Chromium renders it to a PNG.
#   bench/render_report.sh DIR [PNG]        PNG defaults to DIR/report-rendered.png
#   WIDTH=1400 HEIGHT=6000                  the window rendered (the page beyond HEIGHT is cut)
# Installs Debian's chromium if it is missing (apt-get install -y chromium; only this script does).
# Exit status 0: every reference present and the PNG written; 1: a referenced file is missing or Chromium
# wrote no PNG; 2: bad arguments, or no chromium and it could not be installed.
set -uo pipefail
dir=${1:-}
[ -n "$dir" ] && [ -f "$dir/report.html" ] || { echo "render_report.sh: usage: $0 DIR [PNG] (DIR/report.html must exist)" >&2; exit 2; }
page=$(realpath "$dir/report.html")
png=$(realpath -m "${2:-$dir/report-rendered.png}")

/usr/bin/python3 - "$page" <<'PYTHON' || exit 1
import html.parser, os, sys, urllib.parse
page = sys.argv[1]
class References(html.parser.HTMLParser):
    def __init__(self):
        super().__init__()
        self.images, self.links = [], []
    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        if tag == "img": self.images.append(attrs.get("src") or "")
        if tag == "a" and attrs.get("href"): self.links.append(attrs["href"])
parser = References()
with open(page, encoding="utf-8") as f:
    parser.feed(f.read())
missing = []
def local(reference):
    parsed = urllib.parse.urlparse(reference)
    return not parsed.scheme and not reference.startswith("#")
for reference in parser.images + [r for r in parser.links if local(r)]:
    if reference.startswith("data:"): continue
    if not reference or not local(reference):
        missing.append(reference or "(empty src)"); continue
    path = os.path.join(os.path.dirname(page), urllib.parse.unquote(urllib.parse.urlparse(reference).path))
    if not os.path.isfile(path): missing.append(reference)
print(f"render_report.sh: {page}: {len(parser.images)} images, {len(parser.links)} links, {len(missing)} missing")
for m in missing: print(f"render_report.sh: missing: {m}", file=sys.stderr)
sys.exit(1 if missing else 0)
PYTHON

browser=$(command -v chromium || command -v chromium-browser || true)
if [ -z "$browser" ]; then
  echo "render_report.sh: installing chromium (apt-get install -y chromium)"
  { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium; } >/dev/null 2>&1
  browser=$(command -v chromium || true)
  [ -n "$browser" ] || { echo "render_report.sh: chromium is not installed and could not be installed" >&2; exit 2; }
fi
rm -f "$png"
SECONDS=0
timeout 120 "$browser" --headless --no-sandbox --disable-gpu --hide-scrollbars --allow-file-access-from-files \
  --window-size="${WIDTH:-1400},${HEIGHT:-6000}" --virtual-time-budget=10000 --screenshot="$png" "file://$page" \
  >/dev/null 2>&1
if [ ! -s "$png" ]; then
  echo "render_report.sh: chromium wrote no PNG ($png)" >&2
  exit 1
fi
echo "render_report.sh: rendered $png ($(stat -c %s "$png") bytes) in ${SECONDS} s with $("$browser" --version 2>/dev/null)"
