"""`shoal.run` writes what `shoal run` writes: the same world, options and seed give
byte-identical trajectories and vehicle tables, the same summary (digest, counts, physics)
and the same set of files; options are checked with the world file's ranges and named by
their keyword; a world driven by external agents is refused."""

import csv
import json

import pytest

import shoal
from conftest import WORLDS, interruptible, shoal_run

#: Summary entries that depend on the machine or the moment, not on the run.
TIMING = {"wall_s", "real_time_factor", "phases_s", "peak_memory_bytes", "files"}


def without_timing(x):
    if isinstance(x, dict):
        return {k: without_timing(v) for k, v in x.items() if k not in TIMING}
    if isinstance(x, list):
        return [without_timing(v) for v in x]
    return x


def test_python_writes_what_the_command_writes(shoal_bin, tmp_path):
    world = WORLDS / "gossip.toml"
    # (shoal_run adds --no-plots and --no-replay.)
    cli = shoal_run(shoal_bin, world, tmp_path / "cli", "--duration", "4", "--seed", "11",
                    "--mcap")
    py = shoal.run(world, tmp_path / "py", duration=4, seed=11, plots=False, replay=False,
                   mcap=True, quiet=True)
    assert py.ending == "complete"
    assert py.out == tmp_path / "py"
    assert sorted(p.name for p in py.out.iterdir()) == sorted(
        p.name for p in (tmp_path / "cli").iterdir())
    assert not (py.out / "replay.html").exists()
    for name in ["trajectories.csv", "vehicles.csv"]:
        assert (py.out / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    assert py.summary["digest"] == cli["digest"]
    assert without_timing(py.summary) == without_timing(cli)
    rows = list(csv.DictReader(open(py.out / "trajectories.csv")))
    assert float(rows[-1]["t_s"]) == pytest.approx(4.0)
    assert json.loads((py.out / "summary.json").read_text()) == py.summary


def test_the_seed_changes_the_run_and_the_default_folder_is_the_worlds(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    a = shoal.run(WORLDS / "gossip.toml", duration=1, seed=1, plots=False, replay=False,
                  quiet=True)
    assert a.out.parent == tmp_path / "out" and (a.out / "summary.json").exists()
    b = shoal.run(WORLDS / "gossip.toml", tmp_path / "b", duration=1, seed=2, plots=False,
                  replay=False, quiet=True)
    assert a.summary["digest"] != b.summary["digest"]


@pytest.mark.parametrize("kw, words", [
    ({"duration": 0}, ["duration:", "allowed: 0.001 ≤ duration ≤ 1e7 s"]),
    ({"duration": float("nan")}, ["duration:", "allowed"]),
    ({"threads": 0}, ["threads = 0", "1 … 256"]),
])
def test_options_are_checked_with_the_world_files_ranges(tmp_path, kw, words):
    with pytest.raises((shoal.WorldError, ValueError)) as e:
        shoal.run(WORLDS / "gossip.toml", tmp_path / "x", quiet=True, **kw)
    for w in words:
        assert w in str(e.value), str(e.value)
    assert not (tmp_path / "x").exists()


def test_a_world_driven_by_agents_is_refused(tmp_path):
    with pytest.raises(shoal.WorldError, match="external agents"):
        shoal.run(WORLDS / "agents_goto.toml", tmp_path / "x", quiet=True)
    assert not (tmp_path / "x").exists()


def test_a_short_run_of_a_long_mission_is_its_beginning(tmp_path):
    """The default world's missions have steps at 70 s; 2 s of it run, as `shoal run
    --duration 2` does."""
    r = shoal.run(None, tmp_path / "d", duration=2, plots=False, replay=False, quiet=True)
    assert r.summary["simulated_s"] == pytest.approx(2.0)
    assert r.summary["planned_s"] == pytest.approx(2.0)


def test_ctrl_c_stops_a_quiet_run_and_its_outputs_are_written(tmp_path):
    """Quiet or not, the run looks at Python's signals after each chunk of steps: Ctrl-C
    stops it at a step boundary, the outputs up to there are written, then
    KeyboardInterrupt is raised."""
    import signal
    import subprocess
    import sys
    import time

    out = tmp_path / "stopped"
    script = (
        "import shoal\n"
        f"shoal.run({str(WORLDS / 'flock_1000.toml')!r}, {str(out)!r}, duration=600, "
        "plots=False, replay=False, quiet=True)\n"
        "print('finished')\n"
    )
    p = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True, preexec_fn=interruptible)
    deadline = time.monotonic() + 120
    while not (out / ".trajectories.csv.tmp").exists() and time.monotonic() < deadline:
        assert p.poll() is None, p.communicate()
        time.sleep(0.2)
    p.send_signal(signal.SIGINT)
    stdout, err = p.communicate(timeout=120)
    assert "KeyboardInterrupt" in err and "finished" not in stdout, err
    summary = json.loads((out / "summary.json").read_text())
    assert summary["interrupted"] and 0 < summary["simulated_s"] < 600, summary
