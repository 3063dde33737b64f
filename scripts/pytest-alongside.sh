#!/usr/bin/env bash
# Runs pytest for scripts/test.sh while the Rust tests run: `pytest-alongside.sh PYTHON LOG
# [PYTEST ARGS…]` writes pytest's output to LOG, then a last line `exit N` with pytest's exit
# code, and the seconds it took to LOG.time. Under `set -e` a failing pytest would end the
# script before its exit code is written (and the suite's table would say "pytest ?"), hence
# `|| rc=$?`. python/tests/test_scripts.py runs it on a failing test.
set -euo pipefail
python=$1
log=$2
shift 2
start=$(date +%s)
rc=0
"$python" -m pytest -q -p no:cacheprovider "$@" >"$log" 2>&1 || rc=$?
echo "exit $rc" >>"$log"
echo "$(($(date +%s) - start))" >"$log.time"
