"""``shoal.validate`` against ``shoal validate`` on the development logs (../shared/data beside
the repository): the same verdict, effects, parameters and per-channel table as the command
line's report.json, the verdict pinned for the log, runs given as columns read exactly as the
file, and errors that name the setting or the column."""

import json
import subprocess
from pathlib import Path

import numpy as np
import pytest

import shoal

from conftest import REPO

DEV = REPO.parent / "shared" / "data" / "validation_dev"
PINNED = REPO / "crates" / "shoal-sysid" / "tests" / "verdicts" / "validation_dev.tsv"


def dev_log(name: str) -> Path:
    p = DEV / f"{name}.csv"
    assert p.is_file(), f"the development logs belong beside the repository: no {p}"
    return p


def pinned(name: str) -> list:
    for line in PINNED.read_text().splitlines():
        if line.startswith("#") or not line.strip():
            continue
        case, _hidden, found = line.split("\t")
        if case == name:
            return [] if found == "-" else found.split(",")
    raise AssertionError(f"{name} is not in {PINNED}")


def columns(path: Path) -> dict:
    """The log's columns as numpy arrays, by their header names."""
    header = path.read_text().splitlines()[0].split(",")
    data = np.loadtxt(path, delimiter=",", skiprows=1)
    return {h: data[:, i] for i, h in enumerate(header)}


# One diving log and one turning log, each with a hidden effect (the search's settings of
# the pinned table: 20 ms replay, 60/40 split; one search thread, results do not depend on it).
@pytest.mark.parametrize("name", ["dev_y_gain", "dev_h_damp"])
def test_python_gives_the_command_lines_verdict(shoal_bin, tmp_path, name):
    log = dev_log(name)
    out = tmp_path / "cli"
    subprocess.run(
        [shoal_bin, "validate", "--quiet", "--no-plots", "--dt", "0.02", "--threads", "1",
         "--out", out, log],
        check=True, capture_output=True,
    )
    cli = json.loads((out / "report.json").read_text())
    events = []
    r = shoal.validate(log, dt=0.02, threads=1, progress=lambda k, m: events.append(k))
    # The whole verdict (effects, forms, parameters with intervals, evidence, channels) and
    # the candidates are the command line's.
    assert r.data["verdict"] == cli["verdict"]
    assert r.data["candidates"] == cli["candidates"]
    assert sorted(r.effect_names) == pinned(name)
    assert r.verdict == cli["verdict"]["summary"]
    assert {k: c.rmse_after for k, c in r.channels.items()} == {
        k: c["rmse_after"] for k, c in cli["verdict"]["channels"].items()
    }
    for e, want in zip(r.effects, cli["verdict"]["named"]):
        assert [p.value for p in e.parameters] == [p["value"] for p in want["params"]]
    # P(family): each named effect's inclusion probability is its selection frequency, and
    # every "A or B" carries its two families' probabilities.
    assert r.inclusion == cli["verdict"]["inclusion"]
    for e in r.effects:
        assert r.inclusion[e.name] == e.stability
    for a in r.ambiguous:
        assert a["inclusion"] == [r.inclusion[a["effects"][0]], r.inclusion[a["effects"][1]]]
    assert events[0] == "read" and events.count("start") == 1
    assert events[events.index("start") + 1] == "stage" and events.count("stage") >= 4
    # The headline is the mean of the table's gains; the second figure that of the channels
    # the model changes.
    gains = {k: c.gain_pct for k, c in r.channels.items()}
    assert r.validation_gain_pct == pytest.approx(sum(gains.values()) / len(gains), abs=1e-9)
    assert set(r.changed_channels) <= set(gains)
    if r.changed_channels:
        on = [gains[k] for k in r.changed_channels]
        assert r.changed_channels_gain_pct == pytest.approx(sum(on) / len(on), abs=1e-9)
    assert events.count("fit") >= len([c for c in cli["candidates"] if c.get("fit")])
    # The fitted vehicle is the command line's vehicle.toml but for the file name it states.
    assert r.vehicle_toml.splitlines()[3:] == (out / "vehicle.toml").read_text().splitlines()[3:]
    # The report files from Python.
    files = r.write(tmp_path / "py", plots=False)
    assert json.loads(Path(files["json"]).read_text())["verdict"] == cli["verdict"]
    # The next experiment, when the log leaves a question open, is the command line's.
    assert r.next_experiment == cli["verdict"]["next_experiment"]
    nxt = out / "next_experiment.toml"
    if r.next_experiment is None:
        assert r.next_experiment_toml is None and files["next_experiment"] is None
        assert not nxt.exists()
    else:
        assert r.next_experiment_toml == nxt.read_text()
        assert Path(files["next_experiment"]).read_text() == nxt.read_text()


def test_columns_in_memory_are_read_as_the_file():
    log = dev_log("dev_y_gain")
    only = "thrust_gain,damping_error"
    from_file = shoal.validate(log, dt=0.02, threads=1, effects=only)
    from_columns = shoal.validate(("dev_y_gain", columns(log)), dt=0.02, threads=1, effects=only)
    assert from_columns.data["verdict"] == from_file.data["verdict"]
    assert from_columns.channels == from_file.channels
    assert from_file.effect_names == ["thrust_gain"]


def test_errors_name_the_setting_or_the_column():
    log = dev_log("dev_y_gain")
    with pytest.raises(shoal.ValidationError) as e:
        shoal.validate(log, dt=1e-9)
    assert e.value.setting == "dt" and "0.0001 ≤ dt ≤ 0.1 s" in str(e.value)
    with pytest.raises(shoal.ValidationError) as e:
        shoal.validate(log, effects="thrust_gain,gremlins")
    assert e.value.setting == "effects" and "`gremlins`" in str(e.value)
    with pytest.raises(ValueError):  # ValidationError is a ValueError
        shoal.validate(log, channels=["y.speed"])
    cols = columns(log)
    cols["y.r"] = cols["y.r"].copy()
    cols["y.r"][10] = np.nan
    with pytest.raises(shoal.ValidationError) as e:
        shoal.validate(cols, dt=0.02)
    # Row 10 is line 12 of the CSV the columns stand for (line 1: the header).
    assert (e.value.file, e.value.line, e.value.column) == (Path("runs_1.csv"), 12, "y.r"), str(
        e.value
    )
    cols["y.r"] = cols["y.r"][:-1]
    with pytest.raises(ValueError, match="column `y.r` has 4499 values"):
        shoal.validate(cols)
    with pytest.raises(shoal.ValidationError) as e:
        shoal.validate(log, horizon=0.1)
    assert e.value.setting == "horizon" and "0.5 ≤ horizon ≤ 3600 s" in str(e.value)
    with pytest.raises(ValueError, match="allowed choose, open, auto, closed or a number of seconds"):
        shoal.validate(log, horizon="sometimes")


def test_a_horizon_re_anchors_the_replay_and_the_report_says_so():
    log = dev_log("dev_y_gain")
    r = shoal.validate(log, dt=0.02, threads=1, horizon=5, effects="thrust_gain")
    s = r.data["settings"]
    assert s["replay_horizon_s"] == 5.0 and "every 5" in s["replay_why"]
    o = shoal.validate(log, dt=0.02, threads=1, effects="thrust_gain")
    assert o.data["settings"]["replay_horizon_s"] is None
    # Re-anchored, the baseline's heading error is smaller than open loop's.
    yaw = lambda rep: rep.channels["y.yaw"].rmse_before
    assert yaw(r) < yaw(o)
