#!/usr/bin/env bash
# The whole test suite: README's test command, and exactly what CI runs (.ci/run).
#
# Phases, each timed (the table at the end gives the seconds of each, so the CI budget of
# 35 minutes on a bare 2-core machine is measured, not guessed):
#   installs  Python 3 with venv and pip, Chromium, Slurm and munge (Debian's packages, as root
#             with apt-get, when missing), cargo-nextest (from crates.io, when missing); a
#             single-node Slurm cluster started (.ci/slurm-up; stopped on exit).
#   python    the project's venv .venv with the `shoal` package of this checkout
#             (scripts/python-env.sh: PyPI's maturin, numpy, iceoryx2, PettingZoo, Gymnasium,
#             pytest; the extension built with cargo; incremental).
#   build     every test binary, example and bench of the workspace (dev profile).
#   tests     every Rust test with cargo-nextest (.config/nextest.toml: more tests than cores at
#             once, so that waiting tests overlap the CPU-bound ones; searches, browsers and the
#             10⁶-vehicle tests in groups), and at the same time the Python tests (pytest
#             python/tests, against the debug `shoal` binary) — each group's own time is shown.
#   doc+bench the doc tests (cargo test --doc) and every criterion bench once (test mode).
#
# Without root or apt-get, what cannot be installed is said, and the tests that need it fail
# saying what is missing; they never pass unrun. Idempotent: run it as often as you like.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
say() { echo "scripts/test.sh: $*"; }

# Phase timing: `phase NAME` starts a phase (ending the one before); the table is printed on
# exit, whatever the outcome.
phases=()
phase_name=""
phase_start=0
suite_start=$(date +%s)
phase() {
    local now
    now=$(date +%s)
    if [ -n "$phase_name" ]; then phases+=("$phase_name $((now - phase_start))"); fi
    phase_name=$1
    phase_start=$now
    say "── $phase_name"
}
extra_times=()
report() {
    local now
    now=$(date +%s)
    if [ -n "$phase_name" ]; then phases+=("$phase_name $((now - phase_start))"); fi
    phase_name=""
    echo
    echo "scripts/test.sh: time per phase (s)"
    for p in "${phases[@]}" ${extra_times[@]+"${extra_times[@]}"}; do
        printf '  %-34s %6s\n' "${p% *}" "${p##* }"
    done
    printf '  %-34s %6s\n' "total" "$((now - suite_start))"
}

slurm_up=0
pytest_pid=""
cleanup() {
    local rc=$?
    if [ -n "$pytest_pid" ]; then kill "$pytest_pid" 2>/dev/null || true; fi
    if [ "$slurm_up" = 1 ]; then .ci/slurm-down >/dev/null 2>&1 || true; fi
    report
    exit "$rc"
}
trap cleanup EXIT

# ── installs ──────────────────────────────────────────────────────────────────────────────
phase installs
as_root_apt() { command -v apt-get >/dev/null 2>&1 && [ "$(id -u)" = 0 ]; }
if ! python3 -c 'import venv, ensurepip' >/dev/null 2>&1; then
    if as_root_apt; then
        say "installing python3, python3-venv and python3-pip (Debian)"
        apt-get update -qq
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq python3 python3-venv python3-pip >/dev/null
    else
        say "python3 with venv and pip is missing (Debian: apt-get install python3 python3-venv" \
            "python3-pip); the Python tests will fail" >&2
    fi
fi
scripts/install-chromium.sh || say "the replay browser tests will fail" >&2
if ! cargo nextest --version >/dev/null 2>&1; then
    say "installing cargo-nextest (crates.io; a few minutes)"
    cargo install cargo-nextest --locked --quiet
fi
if slurm_out=$(.ci/slurm-up); then
    SHOAL_SLURM_CONF=$(printf '%s\n' "$slurm_out" | sed -n 's/^SLURM_CONF=//p')
    export SHOAL_SLURM_CONF
    slurm_up=1
else
    say "no Slurm cluster (above: why); the Slurm sweep test will fail" >&2
fi

# ── python ────────────────────────────────────────────────────────────────────────────────
phase python
python=$(scripts/python-env.sh)

# ── build ─────────────────────────────────────────────────────────────────────────────────
phase build
cargo build --workspace --tests --examples --benches --quiet
target=$(cargo metadata --format-version 1 --no-deps |
    sed -n 's/.*"target_directory":"\([^"]*\)".*/\1/p')

# ── tests (Rust with nextest; Python alongside) ───────────────────────────────────────────
phase tests
pytest_log=$(mktemp)
SHOAL_BIN="$target/debug/shoal" scripts/pytest-alongside.sh "$python" "$pytest_log" python/tests &
pytest_pid=$!
nextest_rc=0
cargo nextest run --workspace --no-fail-fast || nextest_rc=$?
nextest_end=$(date +%s)
extra_times+=("  nextest (Rust tests) $((nextest_end - phase_start))")
wait "$pytest_pid" || true
pytest_pid=""
extra_times+=("  pytest (alongside) $(cat "$pytest_log.time" 2>/dev/null || echo '?')")
say "pytest python/tests:"
cat "$pytest_log"
pytest_rc=$(sed -n 's/^exit //p' "$pytest_log" | tail -n 1)
rm -f "$pytest_log" "$pytest_log.time"

# ── doc tests and benches ─────────────────────────────────────────────────────────────────
phase "doc tests + benches"
doc_rc=0
cargo test --workspace --doc --quiet || doc_rc=$?
cargo test --workspace --bench '*' --quiet || doc_rc=$?

if [ "$nextest_rc" != 0 ] || [ "${pytest_rc:-1}" != 0 ] || [ "$doc_rc" != 0 ]; then
    say "FAILED: nextest $nextest_rc, pytest ${pytest_rc:-?}, doc tests/benches $doc_rc" >&2
    exit 1
fi
say "every test passed ($root)"
