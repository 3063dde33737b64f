#!/usr/bin/env sh
# The project's one Python environment: a venv in .venv at the repository root (SHOAL_VENV
# overrides the place) holding the `shoal` package built from this checkout with its RL and
# test extras (`pip install "./python[rl,test]"`: numpy, iceoryx2 0.10, PettingZoo, Gymnasium,
# pytest, rosbags, mcap, and cyclonedds, on which the ROS 2 agent package shoal_ros2 runs) and
# maturin, which builds the extension module in release mode with cargo into the
# workspace's target directory. The tests (scripts/test.sh, crates/shoal-cli/tests/python_agent.rs),
# `shoal bench --agents python` and README use it.
#
# Idempotent and incremental: the venv is created once; the package is rebuilt only when a file
# under crates/, python/ or the workspace's Cargo.toml or Cargo.lock is newer than the last
# build (then cargo rebuilds only what changed). An exclusive lock (flock on <venv>.lock) lets
# several callers run it at once. Needs python3 with venv and pip (Debian: apt-get install
# python3-venv python3-pip), cargo, and PyPI.
#
# Prints the venv's interpreter on stdout; progress goes to stderr.
set -eu
cd "$(dirname "$0")/.."
root=$(pwd)
venv=${SHOAL_VENV:-$root/.venv}
say() { echo "scripts/python-env.sh: $*" >&2; }

if ! python3 -c 'import venv, ensurepip' >/dev/null 2>&1; then
    say "python3 with venv and pip is missing (Debian: apt-get install python3 python3-venv python3-pip)"
    exit 1
fi
mkdir -p "$(dirname "$venv")"
exec 9>"$venv.lock"
flock 9

py="$venv/bin/python"
if ! "$py" -c 'import pip' >/dev/null 2>&1; then
    say "creating $venv"
    python3 -m venv --clear "$venv" >&2
fi
stamp="$venv/.shoal-built"
if [ -f "$stamp" ] && "$py" -c 'import shoal, shoal.rl, shoal.agent, pytest, rosbags, mcap, mcap_ros2, jsonschema, cyclonedds' >/dev/null 2>&1 &&
    [ -z "$(find crates python/shoal python/shoal_agent python/shoal_ros2 python/pyproject.toml Cargo.toml Cargo.lock \
        -newer "$stamp" -type f ! -path '*/__pycache__/*' 2>/dev/null | head -n 1)" ]; then
    echo "$py"
    exit 0
fi
pip() { PATH="$venv/bin:$PATH" "$py" -m pip --disable-pip-version-check -q "$@" >&2; }
say "installing the build tools into $venv (PyPI)"
pip install "maturin>=1.9.4,<2"
say "building and installing the shoal package (cargo, release; minutes the first time)"
# No build isolation: the venv's maturin builds, and cargo reuses the workspace's target dir.
pip install --no-build-isolation "$root/python[rl,test]"
touch "$stamp"
echo "$py"
