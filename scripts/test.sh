#!/usr/bin/env sh
# The whole test suite: README's test command, and exactly what CI runs (.ci/run).
#
# 1. Python 3 with venv and pip, for the Python tests (the project's venv .venv, see step P):
#    installed from Debian's packages when missing and this runs as root with apt-get; otherwise
#    those tests fail and say what is missing.
# 2. Chromium, for the replay's headless-browser tests (crates/shoal-sim/tests/replay_browser.rs):
#    scripts/install-chromium.sh installs Debian's package when it is missing and this runs as
#    root with apt-get; otherwise those tests fail and say what is missing.
# 2b. A single-node Slurm cluster for the sweep test (crates/shoal-cli/tests/sweep_slurm.rs):
#    .ci/slurm-up installs Debian's slurm-wlm and munge when missing (root, apt-get), tears down
#    a cluster a crashed earlier run left behind, and starts one; .ci/slurm-down stops it when
#    this script ends. When it cannot start, the Slurm test fails and says why.
# 3. cargo test --workspace: every test (unit, integration, doc); it builds the examples too.
# 4. cargo test --workspace --bench '*': every criterion bench, compiled and run once (test mode).
# 5. Each root example once, on a short setting, into a temporary folder.
# P. The Python package (python/, built with maturin from crates/shoal-py): before step 3,
#    scripts/python-env.sh makes .venv (from PyPI: maturin, numpy, iceoryx2, PettingZoo,
#    Gymnasium, pytest) and builds and installs the package (release; incremental); after
#    step 5, pytest runs python/tests against it and the `shoal` binary step 3 built.
#
# Idempotent: run it as often as you like.
set -eu
cd "$(dirname "$0")/.."
root=$(pwd)

# 1. Python 3 with venv and pip.
if ! python3 -c 'import venv, ensurepip' >/dev/null 2>&1; then
    if command -v apt-get >/dev/null 2>&1 && [ "$(id -u)" = 0 ]; then
        echo "scripts/test.sh: installing python3, python3-venv and python3-pip (Debian)"
        apt-get update -qq
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq python3 python3-venv python3-pip >/dev/null
    else
        echo "scripts/test.sh: python3 with venv and pip is missing (Debian: apt-get install" \
            "python3 python3-venv python3-pip); the Python agent tests will fail" >&2
    fi
fi

# 2. Chromium (the script says what it did; without root or apt-get it only warns here).
scripts/install-chromium.sh || echo "scripts/test.sh: the replay browser tests will fail" >&2

# 2b. Slurm, for the sweep test; stopped (with the examples' folder removed) on exit.
slurm_up=0
cleanup() {
    if [ "$slurm_up" = 1 ]; then .ci/slurm-down; fi
    rm -rf "${tmp:-}"
}
trap cleanup EXIT
if slurm_out=$(.ci/slurm-up); then
    SHOAL_SLURM_CONF=$(printf '%s\n' "$slurm_out" | sed -n 's/^SLURM_CONF=//p')
    export SHOAL_SLURM_CONF
    slurm_up=1
else
    echo "scripts/test.sh: no Slurm cluster (above: why); the Slurm sweep test will fail" >&2
fi

# P (before the tests). The Python package in the project's venv (.venv).
echo "scripts/test.sh: building the Python package into .venv (scripts/python-env.sh)"
python=$(scripts/python-env.sh)

# 3. The tests.
cargo test --workspace

# 4. The benches, once each.
cargo test --workspace --bench '*'

# 5. The root examples, from the binaries step 3 built, on short settings.
target=$(cargo metadata --format-version 1 --no-deps |
    sed -n 's/.*"target_directory":"\([^"]*\)".*/\1/p')
examples="$target/debug/examples"
tmp=$(mktemp -d) # removed by cleanup (2b)
need() {
    for f in "$@"; do
        [ -s "$f" ] || { echo "scripts/test.sh: $f was not written" >&2; exit 1; }
    done
}
echo "scripts/test.sh: running the examples into $tmp"
# The paper's Section 5 runs (five short worlds) and their figures and table.
"$examples/paper_section5" "$tmp/paper"
need "$tmp/paper/metrics.md" "$tmp/paper/diving.png" "$tmp/paper/buoyancy.svg" "$tmp/paper/turning.png"
# The link-budget figure.
"$examples/link_budget_curves" "$tmp/link_budget"
need "$tmp/link_budget.png" "$tmp/link_budget.svg"
# Two 120 s logs with a hidden effect (it writes out/hidden in the working folder).
(cd "$tmp" && "$examples/hidden_effect")
need "$tmp/out/hidden/dive_a.csv" "$tmp/out/hidden/dive_b.csv"
# The medium's profile, on a 30-vehicle swarm instead of 1,000.
"$examples/profile_comm" 30

# P (after the tests). The Python tests, against the debug `shoal` binary of step 3.
echo "scripts/test.sh: the Python tests (pytest python/tests)"
SHOAL_BIN="$target/debug/shoal" "$python" -m pytest -q -p no:cacheprovider python/tests

echo "scripts/test.sh: tests, benches and examples passed ($root)"
