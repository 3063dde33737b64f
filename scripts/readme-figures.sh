#!/usr/bin/env sh
# Regenerates the README's pictures and its sample output from a real run of the default world:
#
#   docs/img/default.gif      the animation the README opens with (`shoal render`)
#   docs/img/default_top.png  the run's top-view plot
#   docs/img/replay.png       replay.html in headless Chromium at t = 40 s
#   README.md                 the block between <!-- sample-output:start/end --> (what
#                             `cargo run --release -- run` printed)
#
# Usage: scripts/readme-figures.sh   (from anywhere; needs chromium for the screenshot:
# scripts/install-chromium.sh). The run goes to out/default-swarm, as for a user.
set -eu
cd "$(dirname "$0")/.."

cargo build --release -p shoal-cli
shoal=target/release/shoal
out=out/default-swarm
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# The run, printed as a user sees it (stderr's progress bar is hidden when not a terminal).
echo "readme-figures: running the default world"
"$shoal" run --out "$out" >"$tmp/stdout" 2>"$tmp/stderr"
{
    echo '$ cargo run --release -- run'
    grep '^shoal: ' "$tmp/stderr" || true
    cat "$tmp/stdout"
} | sed -e '/^$/N;/^\n$/D' >"$tmp/sample.raw"
# Without trailing blank lines (command substitution drops them).
printf '%s\n' "$(cat "$tmp/sample.raw")" >"$tmp/sample"

cp "$out/top.png" docs/img/default_top.png
"$shoal" render "$out" --gif docs/img/default.gif --view both --width 560

if command -v chromium >/dev/null 2>&1; then
    timeout 120 chromium --headless --no-sandbox --disable-dev-shm-usage \
        --use-angle=swiftshader --enable-unsafe-swiftshader --window-size=1280,720 \
        --hide-scrollbars --virtual-time-budget=8000 \
        --screenshot="$(pwd)/docs/img/replay.png" \
        "file://$(pwd)/$out/replay.html#t=40" 2>/dev/null
    echo "readme-figures: wrote docs/img/replay.png"
else
    echo "readme-figures: chromium is missing (scripts/install-chromium.sh); docs/img/replay.png kept" >&2
fi

# The sample output block of README.md.
awk -v sample="$tmp/sample" '
    /<!-- sample-output:start -->/ {
        print; print "```text"
        while ((getline line < sample) > 0) print line
        print "```"; skip = 1; next
    }
    /<!-- sample-output:end -->/ { skip = 0 }
    !skip { print }
' README.md >"$tmp/README.md"
if ! grep -q 'sample-output:start' "$tmp/README.md"; then
    echo "readme-figures: README.md has no <!-- sample-output:start --> marker" >&2
    exit 1
fi
cp "$tmp/README.md" README.md
echo "readme-figures: updated docs/img/default.gif, docs/img/default_top.png and README.md's sample output"
