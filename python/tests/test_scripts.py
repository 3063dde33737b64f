"""The suite's own scripts where a mistake would hide failures: scripts/pytest-alongside.sh,
which runs the Python tests beside the Rust ones for scripts/test.sh, keeps pytest's exit code
(under `set -e` a failing pytest once ended the script before the code was written, and the
suite's table said "pytest ?")."""

import subprocess
import sys

from conftest import REPO

SCRIPT = REPO / "scripts" / "pytest-alongside.sh"


def run_alongside(tmp_path, body: str) -> list:
    tests = tmp_path / "t"
    tests.mkdir()
    (tests / "test_one.py").write_text(body)
    log = tmp_path / "log"
    p = subprocess.run([str(SCRIPT), sys.executable, str(log), str(tests)],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    assert (tmp_path / "log.time").read_text().strip().isdigit()
    return log.read_text().splitlines()


def test_a_failing_python_test_leaves_its_exit_code(tmp_path):
    lines = run_alongside(tmp_path, "def test_fails():\n    assert 1 == 2\n")
    assert lines[-1] == "exit 1", lines[-5:]
    assert any("1 failed" in l for l in lines), lines


def test_a_passing_python_test_leaves_exit_0(tmp_path):
    lines = run_alongside(tmp_path, "def test_passes():\n    assert 2 == 2\n")
    assert lines[-1] == "exit 0", lines[-5:]
