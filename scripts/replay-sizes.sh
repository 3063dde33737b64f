#!/usr/bin/env sh
# Replay sizes and headless frame times of real runs (not in CI: minutes of work):
# the default world (12 vehicles, 100 s) and beaconing grids of 1,000 and 10,000 μAUV² (100 s),
# each run with `shoal run --no-plots`, then every replay.html timed in headless Chromium by
# scripts/replay-frame-times.py. Prints the run times, the replay sizes (MB) and the frame-time
# table. Usage: scripts/replay-sizes.sh [SECONDS_OF_PLAYBACK, default 10]
set -eu
cd "$(dirname "$0")/.."
secs=${1:-10}
cargo build --release -p shoal-cli
shoal=target/release/shoal
tmp=${TMPDIR:-/tmp}/shoal-replay-sizes
rm -rf "$tmp"
mkdir -p "$tmp"

# A grid of $1 vehicles ($2 columns, 1.2 m apart) beaconing a 20-byte frame every 2 s through
# a ring of four modems, cruising north at 3 cm/s from t = 5 s.
grid_world() {
    n=$1
    cols=$2
    rows=$(((n + cols - 1) / cols))
    cat <<EOF
name = "grid $n"
seed = 7
duration = 100.0
dt = 0.01

[pool]
size = [$(awk "BEGIN { print $cols * 1.2 + 6 }"), $(awk "BEGIN { print $rows * 1.2 + 2 }"), 3.0]

[[vehicles]]
name = "grid"
count = $n
grid = { origin = [1.0, 1.0, 1.5], spacing = [1.2, 1.2], columns = $cols }
mission = [{ t = 0, mode = "auto", depth = 1.5, yaw_deg = 0 }, { t = 5, surge = 0.03 }]
behaviour = { kind = "beacon", period = 2.0, payload_bytes = 20, jitter = 0.5 }
EOF
    for m in "front 0.125 0.0 1.0 0.0" "right 0.0 0.078 0.0 1.0" \
        "back -0.125 0.0 -1.0 0.0" "left 0.0 -0.078 0.0 -1.0"; do
        set -- $m
        printf '\n[[vehicles.model.modems]]\nname = "%s"\nposition = [%s, %s, 0.0]\ndirection = [%s, %s, 0.0]\n' \
            "$1" "$2" "$3" "$4" "$5"
    done
    printf '\n[output]\nrecord_hz = 0.1\nplots = false\n'
}
grid_world 1000 40 >"$tmp/grid1000.toml"
grid_world 10000 100 >"$tmp/grid10000.toml"

pages=""
for w in default grid1000 grid10000; do
    if [ "$w" = default ]; then world=""; else world="$tmp/$w.toml"; fi
    start=$(date +%s)
    # shellcheck disable=SC2086
    "$shoal" run $world --quiet --no-plots --out "$tmp/$w" >"$tmp/$w.txt"
    end=$(date +%s)
    bytes=$(stat -c %s "$tmp/$w/replay.html")
    echo "$w: run $((end - start)) s, replay.html $(awk "BEGIN { printf \"%.2f\", $bytes / 1e6 }") MB"
    pages="$pages $tmp/$w/replay.html"
done
# shellcheck disable=SC2086
python3 scripts/replay-frame-times.py --seconds "$secs" $pages
