#!/usr/bin/env sh
# Times whole `shoal run` processes of the benchmark swarms (examples/bench_world.rs: the
# quiet 0.6 m grid and the beaconing 1.5 m grid of `shoal bench`), this build beside another
# shoal binary, alternating per row: wall time and CPU time of the whole process (set-up,
# stepping, every output) for 8 s simulated, on 1 and 2 threads.
#
#   scripts/run-vs-bench.sh OTHER_SHOAL [VEHICLES]      (default: 10000)
#
# Release build; runs go to a temporary folder that is removed. Benchmark, not a test: run it
# on a quiet machine and compare within one run.
set -eu
cd "$(dirname "$0")/.."
other=$1
n=${2:-10000}
cargo build --release -q -p shoal-cli
cargo build --release -q -p shoal --example bench_world
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
printf "%-10s %8s %7s %12s %12s %12s %12s %8s\n" world vehicles threads "this wall s" "this cpu s" "other wall s" "other cpu s" "other/this"
for world in quiet beaconing; do
    target/release/examples/bench_world "$n" "$world" >"$tmp/$world.toml"
    for threads in 1 2; do
        for who in this other; do
            bin=target/release/shoal
            [ "$who" = other ] && bin=$other
            /usr/bin/time -f "%e %U %S" -o "$tmp/time" "$bin" run "$tmp/$world.toml" \
                --duration 8 --threads "$threads" --out "$tmp/out-$who" --quiet >/dev/null
            read -r wall user sys <"$tmp/time"
            eval "${who}_wall=$wall ${who}_cpu=$(awk -v u="$user" -v s="$sys" 'BEGIN { print u + s }')"
            rm -rf "$tmp/out-$who"
        done
        printf "%-10s %8d %7d %12.2f %12.2f %12.2f %12.2f %8.2f\n" "$world" "$n" "$threads" \
            "$this_wall" "$this_cpu" "$other_wall" "$other_cpu" \
            "$(awk -v o="$other_wall" -v t="$this_wall" 'BEGIN { print o / t }')"
    done
done
