#!/usr/bin/env sh
# Measures the memory a vehicle takes in `shoal run`: the peak resident memory of the whole
# process (`/usr/bin/time -v`) and as the run's summary reports it (peak_memory_bytes), each
# divided by the number of vehicles. This is the figure README.md states (*Large worlds*).
#
#   scripts/memory-per-vehicle.sh [VEHICLES] [quiet|beacon]      (default: 100000 quiet)
#
# quiet: μAUV² on a 0.6 m grid (1000 columns) in auto mode, 0.5 s, one trajectory row each.
# beacon: the same on a 1.5 m grid, each with a ring of four modems beaconing a 32-byte frame
# once a second for 5 s (`shoal bench`'s beaconing swarm), so that every vehicle hears its
# neighbours and keeps their reception statistics. Release build; the run goes to a
# temporary folder that is removed.
set -eu
cd "$(dirname "$0")/.."
n=${1:-100000}
kind=${2:-quiet}

cargo build --release -q -p shoal-cli
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

columns=1000
[ "$n" -lt "$columns" ] && columns=$n
rows=$(( (n + columns - 1) / columns ))
case $kind in
quiet) spacing=0.6 duration=0.5 ;;
beacon) spacing=1.5 duration=5.0 ;;
*) echo "memory-per-vehicle: kind is quiet or beacon, not $kind" >&2; exit 2 ;;
esac
awk -v n="$n" -v c="$columns" -v r="$rows" -v s="$spacing" -v d="$duration" -v k="$kind" 'BEGIN {
    printf "name = \"memory %s %d\"\nduration = %s\ndt = 0.01\n", k, n, d
    printf "[pool]\nsize = [%.1f, %.1f, 3.0]\n", c * s + 2, r * s + 2
    printf "[output]\nrecord_hz = 1\n"
    printf "[[vehicles]]\nname = \"b\"\ncount = %d\n", n
    printf "grid = { origin = [1.0, 1.0, 1.0], spacing = [%s, %s], columns = %d }\n", s, s, c
    printf "mission = [{ t = 0, mode = \"auto\", depth = 1.3, yaw_deg = 45 }]\n"
    if (k == "beacon") {
        printf "behaviour = { kind = \"beacon\", period = 1.0, payload_bytes = 26, jitter = 0.05 }\n"
        printf "[[vehicles.model.modems]]\nname = \"front\"\nposition = [0.125, 0.0, 0.0]\ndirection = [1.0, 0.0, 0.0]\n"
        printf "[[vehicles.model.modems]]\nname = \"right\"\nposition = [0.0, 0.078, 0.0]\ndirection = [0.0, 1.0, 0.0]\n"
        printf "[[vehicles.model.modems]]\nname = \"back\"\nposition = [-0.125, 0.0, 0.0]\ndirection = [-1.0, 0.0, 0.0]\n"
        printf "[[vehicles.model.modems]]\nname = \"left\"\nposition = [0.0, -0.078, 0.0]\ndirection = [0.0, -1.0, 0.0]\n"
    }
}' >"$tmp/world.toml"

/usr/bin/time -v target/release/shoal run "$tmp/world.toml" --out "$tmp/out" --quiet \
    2>"$tmp/time" >/dev/null
peak_kb=$(awk -F': ' '/Maximum resident set size/ { print $2 }' "$tmp/time")
summary_b=$(sed -n 's/.*"peak_memory_bytes": \([0-9]*\).*/\1/p' "$tmp/out/summary.json")
awk -v n="$n" -v p="$peak_kb" -v s="$summary_b" -v k="$kind" 'BEGIN {
    printf "%s, %d vehicles: peak resident memory %.0f MB = %.2f KB per vehicle", k, n, p * 1024 / 1e6, p / n
    printf " (the summary: %.0f MB, %.2f KB per vehicle)\n", s / 1e6, s / 1024 / n
}'
