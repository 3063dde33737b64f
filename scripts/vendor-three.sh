#!/usr/bin/env sh
# Regenerates the vendored three.js bundle of replay.html:
#   crates/shoal-record/assets/replay/three-<version>.min.js   (esbuild IIFE, global THREE)
#   crates/shoal-record/assets/replay/THREE-LICENSE            (three's LICENSE, MIT)
#
# The export list lives in crates/shoal-record/assets/replay/three-entry.js: only those names are
# bundled (tree-shaken, minified, the MIT @license header kept by --legal-comments=inline).
# Needs node and npm (Debian: apt-get install -y nodejs npm) and the npm registry; cargo and CI
# never do: the bundle is committed and embedded with include_str!.
#
# Usage: scripts/vendor-three.sh [three-version]   (default 0.187.0; another version also needs
# the file name in crates/shoal-record/src/replay/html.rs changed). Idempotent: same inputs give
# the same bundle.
set -eu
cd "$(dirname "$0")/.."
version=${1:-0.187.0}
esbuild_version=0.28.2
assets=crates/shoal-record/assets/replay
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "scripts/vendor-three.sh: npm install three@$version esbuild@$esbuild_version into $tmp"
(cd "$tmp" && npm init -y >/dev/null &&
    npm install --no-audit --no-fund --silent "three@$version" "esbuild@$esbuild_version" >/dev/null)
cp "$assets/three-entry.js" "$tmp/entry.js"
(cd "$tmp" && ./node_modules/.bin/esbuild entry.js --bundle --minify --format=iife \
    --global-name=THREE --legal-comments=inline --log-level=warning --outfile=three.min.js)
# The page embeds the bundle between <script> tags: it must not end the element early.
if grep -q -i -e '</script' -e '<!--' "$tmp/three.min.js"; then
    echo "scripts/vendor-three.sh: the bundle contains </script or <!--; cannot embed it" >&2
    exit 1
fi
cp "$tmp/three.min.js" "$assets/three-$version.min.js"
cp "$tmp/node_modules/three/LICENSE" "$assets/THREE-LICENSE"
echo "scripts/vendor-three.sh: wrote $assets/three-$version.min.js" \
    "($(wc -c <"$assets/three-$version.min.js") bytes) and $assets/THREE-LICENSE"
