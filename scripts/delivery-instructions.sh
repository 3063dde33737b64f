#!/usr/bin/env sh
# Counts the instructions the optical medium's delivery phase executes per reception attempt,
# with valgrind's callgrind: deterministic (the same binary and world give the same count on
# every run), so that a change to the delivery can be judged without the noise of timing on a
# shared virtual machine — whose CPU often offers no performance counters either. The world
# is `shoal bench`'s beaconing swarm (examples/bench_world.rs), one thread; attempts are read
# from the run's summary.json.
#
#   scripts/delivery-instructions.sh [OTHER_SHOAL] [VEHICLES] [SECONDS]
#                                                    (defaults: none, 10000, 3)
#
# With OTHER_SHOAL (another shoal binary, e.g. an older build), it is counted too, and the
# ratio printed. Needs valgrind (Debian: apt-get install valgrind); about a minute per binary
# at the defaults. A measurement, not a test: the counts are instructions, not time, though
# the delivery phase is bound by them (its data fits the caches).
set -eu
cd "$(dirname "$0")/.."
other=${1:-}
n=${2:-10000}
seconds=${3:-3}
command -v valgrind >/dev/null || {
    echo "delivery-instructions: valgrind is missing (apt-get install valgrind)" >&2
    exit 2
}
cargo build --release -q -p shoal-cli
cargo build --release -q -p shoal --example bench_world
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
target/release/examples/bench_world "$n" beaconing >"$tmp/world.toml"

# Prints "instructions attempts" of binary $1.
count() {
    valgrind --tool=callgrind --callgrind-out-file="$tmp/callgrind.out" \
        --toggle-collect='shoal_sim::comm::systems::comm_deliver_system*' \
        "$1" run "$tmp/world.toml" --threads 1 --duration "$seconds" --no-plots --no-replay \
        --out "$tmp/out" --quiet 2>"$tmp/log" >/dev/null
    ir=$(sed -n 's/.*Collected : \([0-9]*\).*/\1/p' "$tmp/log")
    attempts=$(python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["comm"]["receptions"]["attempts"])' "$tmp/out/summary.json")
    rm -rf "$tmp/out"
    echo "$ir $attempts"
}

report() {
    awk -v who="$1" -v ir="$2" -v a="$3" -v n="$n" -v s="$seconds" 'BEGIN {
        printf "%-6s %d vehicles, %s s: %.3f G instructions in the delivery phase, %d attempts, %.0f per attempt\n", who, n, s, ir / 1e9, a, ir / a
    }'
}

set -- $(count target/release/shoal)
this_ir=$1 this_attempts=$2
report this "$this_ir" "$this_attempts"
if [ -n "$other" ]; then
    set -- $(count "$other")
    report other "$1" "$2"
    awk -v t="$this_ir" -v ta="$this_attempts" -v o="$1" -v oa="$2" 'BEGIN {
        printf "this / other, per attempt: %.3f%s\n", (t / ta) / (o / oa), (ta == oa ? "" : " (the attempts differ: the runs are not the same physics)")
    }'
fi
