#!/usr/bin/env bash
# The CPU cost of `shoal validate`'s search side by side with an older commit: builds
# examples/search_speed.rs (release) for the current checkout and for BASE_COMMIT (in a
# temporary git worktree, removed afterwards, the program's source copied into it; for a base
# from before the crate shoal-testkit its `shoal_testkit::` paths become `shoal::sysid::` (and
# from before sysid's stage folders, its `log::run` and `evaluate::dataset` paths the old ones), where
# those modules were then), runs the two on each selected case alternately (base, current,
# base, current, … so that both see the same machine load) and prints per case the CPU seconds
# of both, their ratio and whether the verdicts are equal, then the totals and the machine. A
# benchmark: nothing is asserted about speed; the exit status is 1 when a verdict differs (a
# correctness finding), 2 on bad usage.
#
#   scripts/search-speed.sh [BASE_COMMIT] [--quick] [--case PATTERN]… [--threads N] [--out DIR]
#   scripts/search-speed.sh --table BASE.csv CURRENT.csv
#
#   BASE_COMMIT     the commit to compare with [6ace9bd]
#   --quick         seven representative cases: a single, a pair and a null in each experiment,
#                   the long log (about 10 minutes of CPU for both programs together)
#   --case PATTERN  cases whose name contains PATTERN (repeatable; see `--list` of the program);
#                   the 600 s log as a user has it is `long_h_thruster_lag_600s`
#   --threads N     worker threads of each search [1]
#   --out DIR       keep the two programs' rows there (base.csv, current.csv)
#   --table A B     only the table (and exit status) of two such files, rows in the same order
#
# The current checkout builds in its target directory (CARGO_TARGET_DIR, else target/), the base
# in search-speed-base inside it, kept between runs so that after the first time (a release
# build of every dependency: minutes) only the workspace crates are rebuilt. One directory for
# both trees would not do: cargo names a workspace crate's artifacts by its path relative to
# the workspace root, the same in both trees, and judges them fresh by the sources'
# modification times, so one tree would link the other's crates. Without --quick or --case
# every case of the pinned subset and the long log are run: about an hour of CPU.
set -euo pipefail

usage() { sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; }

base=6ace9bd
quick=()
patterns=()
threads=1
out=
table_of=()
while (($#)); do
    case $1 in
    --table)
        table_of=("${2:?--table needs two files}" "${3:?--table needs two files}")
        shift 2
        ;;
    --out)
        out=${2:?--out needs a folder}
        shift
        ;;
    --quick) quick=(--quick) ;;
    --case)
        patterns+=("${2:?--case needs a pattern}")
        shift
        ;;
    --threads)
        threads=${2:?--threads needs a number}
        shift
        ;;
    -h | --help)
        usage
        exit 0
        ;;
    -*)
        echo "search-speed: unknown option $1" >&2
        usage >&2
        exit 2
        ;;
    *) base=$1 ;;
    esac
    shift
done

# table BASE.csv CURRENT.csv: rows of the program's CSV (case,cpu_s,wall_s,verdict; a header
# line is skipped) joined by case in CURRENT's order: CPU base, CPU current, their ratio and
# whether the verdicts are equal (an error or a case missing in BASE never is), then the totals;
# exits 1 when a verdict differs.
table() {
    awk -F, '
        function secs(x) { return x == "" ? "-" : x " s" }
        FNR == 1 && $1 == "case" { next }
        NR == FNR { base_cpu[$1] = $2; base_v[$1] = $4; next }
        {
            n++; name[n] = $1; cur_cpu[n] = $2; cur_v[n] = $4
            if (length($1) > w) w = length($1)
        }
        END {
            if (w < 18) w = 18
            fmt = "%-" w "s  %10s  %10s  %6s  %s\n"
            printf fmt, "case", "CPU base", "CPU cur.", "ratio", "verdicts equal"
            differ = 0
            for (i = 1; i <= n; i++) {
                c = name[i]
                if (!(c in base_v)) base_v[c] = "missing"
                same[i] = (base_v[c] == cur_v[i] && cur_v[i] !~ /^error/)
                differ += !same[i]
                ratio = (cur_cpu[i] > 0) ? sprintf("%.2f", base_cpu[c] / cur_cpu[i]) : "-"
                printf fmt, c, secs(base_cpu[c]), secs(cur_cpu[i]), ratio, same[i] ? "yes" : "NO"
                tb += base_cpu[c]; tc += cur_cpu[i]
            }
            overall = (tc > 0) ? sprintf("%.2f", tb / tc) : "-"
            printf fmt, "total (" n " case(s))", sprintf("%.2f s", tb), sprintf("%.2f s", tc), \
                overall, differ ? differ " differ" : "all equal"
            printf "\noverall ratio (total CPU base / total CPU current): %s\n", overall
            for (i = 1; i <= n; i++)
                if (!same[i])
                    printf "verdicts of %s: base %s, current %s\n", name[i], base_v[name[i]], cur_v[i]
            exit differ ? 1 : 0
        }' "$1" "$2"
}

if ((${#table_of[@]})); then
    table "${table_of[@]}"
    exit
fi

root=$(git rev-parse --show-toplevel)
cd "$root"
base_rev=$(git rev-parse --verify --quiet "$base^{commit}") || {
    echo "search-speed: $base is not a commit" >&2
    exit 2
}
current_rev=$(git rev-parse --short HEAD)
git diff --quiet HEAD -- . || current_rev+=" + uncommitted changes"
target=$(realpath -m "${CARGO_TARGET_DIR:-$root/target}")
work=$(mktemp -d -t search-speed.XXXXXX)
cleanup() {
    git -C "$root" worktree remove --force "$work/base" 2>/dev/null || true
    git -C "$root" worktree prune
    rm -rf "$work"
}
trap cleanup EXIT

# build TREE TARGET OUT: the release program of TREE built in TARGET, copied to OUT.
build() {
    echo "search-speed: building in $1 (target $2)" >&2
    (cd "$1" && CARGO_TARGET_DIR=$2 nice -n 10 cargo build --release --quiet --example search_speed)
    cp "$2/release/examples/search_speed" "$3"
}
git worktree add --detach --quiet "$work/base" "$base_rev"
cp examples/search_speed.rs "$work/base/examples/"
if [[ ! -d $work/base/crates/shoal-testkit ]]; then
    sed -i 's/\bshoal_testkit::/shoal::sysid::/g' "$work/base/examples/search_speed.rs"
fi
# A base from before sysid's stage folders (log/, evaluate/) has the modules at the top.
if [[ ! -d $work/base/crates/shoal-sysid/src/log ]]; then
    sed -i 's/\bshoal::sysid::log::run::/shoal::sysid::run::/g; s/\bshoal::sysid::evaluate::dataset::/shoal::sysid::data::/g' \
        "$work/base/examples/search_speed.rs"
fi
build "$work/base" "$target/search-speed-base" "$work/search_speed.base"
build "$root" "$target" "$work/search_speed.current"

mapfile -t cases < <("$work/search_speed.current" --list "${quick[@]}" "${patterns[@]}")
if ((${#cases[@]} == 0)); then
    echo "search-speed: no case matches ${patterns[*]}" >&2
    exit 2
fi
load_start=$(cut -d' ' -f1-3 /proc/loadavg)
echo "search-speed: ${#cases[@]} case(s), $threads thread(s), base ${base_rev:0:7}, current $current_rev; load average $load_start" >&2

# run SIDE CASE: one search by SIDE's program; appends its row (case,cpu_s,wall_s,verdict) to
# $work/SIDE.csv, an `error: …` row when the program fails.
run() {
    local one="$work/$1.one.csv" rc=0
    rm -f "$one"
    "$work/search_speed.$1" --exact "$2" --threads "$threads" --csv "$one" >/dev/null || rc=$?
    if ((rc == 0)) && [[ -s $one ]]; then
        tail -n +2 "$one" >>"$work/$1.csv"
    else
        echo "$2,,,error: the program exited with status $rc" >>"$work/$1.csv"
    fi
    tail -n 1 "$work/$1.csv" | awk -F, -v s="$1" '{ printf "  %-8s %9s s CPU  %s\n", s, $2, $4 }' >&2
}
echo "case,cpu_s,wall_s,verdict" | tee "$work/base.csv" >"$work/current.csv"
i=0
for c in "${cases[@]}"; do
    i=$((i + 1))
    echo "[$i/${#cases[@]}] $c" >&2
    run base "$c"
    run current "$c"
done

load_end=$(cut -d' ' -f1-3 /proc/loadavg)
model=$(lscpu | sed -n 's/^Model name: *//p' | head -n 1)
cpus=$(nproc)
cores=$(lscpu -p=CORE 2>/dev/null | grep -v '^#' | sort -u | wc -l)
echo
echo "search CPU time, base ${base_rev:0:7} vs current $current_rev, $threads thread(s)"
echo "machine: $model, $cpus CPU(s), $cores core(s); load average $load_start at the start, $load_end at the end"
echo
if [[ -n $out ]]; then
    mkdir -p "$out"
    cp "$work/base.csv" "$work/current.csv" "$out/"
fi
table "$work/base.csv" "$work/current.csv"
