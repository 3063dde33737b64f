#!/usr/bin/env sh
# Installs Chromium for the replay's headless-browser tests (crates/shoal-record/tests/replay_browser.rs)
# and for measuring the viewer (scripts/replay-frame-times.py).
#
# Idempotent: does nothing when `chromium` is already on PATH. Otherwise, as root on Debian/Ubuntu
# with apt-get, installs the distribution's `chromium` package (Debian 12: ~165 MB download,
# ~505 MB on disk, ~50 s). No browser is ever downloaded from anywhere but the package registry.
# Without root or apt-get it says what to install and exits with status 1.
set -eu
if command -v chromium >/dev/null 2>&1; then
    echo "scripts/install-chromium.sh: chromium already installed ($(command -v chromium))"
    exit 0
fi
if command -v apt-get >/dev/null 2>&1 && [ "$(id -u)" = 0 ]; then
    echo "scripts/install-chromium.sh: installing chromium (Debian package; ~165 MB download)"
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null
    command -v chromium >/dev/null 2>&1 || {
        echo "scripts/install-chromium.sh: apt-get installed chromium but it is not on PATH" >&2
        exit 1
    }
    echo "scripts/install-chromium.sh: installed $(chromium --version 2>/dev/null || echo chromium)"
else
    echo "scripts/install-chromium.sh: chromium is missing; install it as root with" \
        "'apt-get update && apt-get install -y chromium' (Debian/Ubuntu)" >&2
    exit 1
fi
