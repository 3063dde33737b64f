"""`shoal validate` on rosbag2s written by a real ROS 2 tool chain (PyPI's `rosbags`, not
shoal): the development logs of ../shared/data/validation_dev as a ROS 2 logger records them
(`rosbag_writer.py`: a topic per signal, each at its own rate and clock, PWM commands on
change, absolute pressure at 40 Hz, header stamps with jitter, a measurement topic starting
late, a vendor message type, a topic nobody maps) give the verdicts pinned for their CSVs — the same effects
(crates/shoal-sysid/tests/verdicts/validation_dev.tsv), forms and parameters within ±10 %
(validation_dev_fits.tsv), with the development-log test's settings: 20 ms replay, 60/40
split — and, without a search, the same run row by row: each row of the bag's run (read by
`shoal.read_log`) holds the CSV's commands in force at its time and the CSV's sample it was
stamped from. And bad bags and mappings give errors that name what and where.

The two logs whose searches take longest (`dev_h_combo`, `dev_h_inflow`; the CSV test leaves
them to its campaign too) run only with SHOAL_CAMPAIGN=1."""

import json
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import rosbag_writer as bags
import shoal
from conftest import REPO

DEV = REPO.parent / "shared" / "data" / "validation_dev"
PINNED = REPO / "crates" / "shoal-sysid" / "tests" / "verdicts" / "validation_dev.tsv"
PINNED_FITS = PINNED.with_name("validation_dev_fits.tsv")
#: How far a fitted parameter may be from its pinned value (fraction of it; as the Rust test).
FIT_TOL = 0.10
CAMPAIGN_ONLY = {"dev_h_combo", "dev_h_inflow"}


def pinned() -> dict:
    out = {}
    for line in PINNED.read_text().splitlines():
        if line.startswith("#") or not line.strip():
            continue
        case, _hidden, found = line.split("\t")
        out[case] = [] if found == "-" else found.split(",")
    return out


PINNED_VERDICTS = pinned()


def pinned_fits() -> dict:
    """Case → (sorted `effect/form`s, {`effect.param`: value})."""
    out = {}
    for line in PINNED_FITS.read_text().splitlines():
        if line.startswith("#") or not line.strip():
            continue
        case, forms, params = line.split("\t")
        forms = [] if forms == "-" else forms.split(",")
        params = {} if params == "-" else {
            k: float(v) for k, v in (p.split("=") for p in params.split(","))}
        out[case] = (sorted(forms), params)
    return out


PINNED_FITS_BY_CASE = pinned_fits()


def case_params():
    for name in sorted(PINNED_VERDICTS):
        marks = []
        if name in CAMPAIGN_ONLY and os.environ.get("SHOAL_CAMPAIGN") != "1":
            marks.append(pytest.mark.skip(reason="campaign only (SHOAL_CAMPAIGN=1)"))
        yield pytest.param(name, marks=marks)


def bag_of(name: str, tmp: Path) -> tuple:
    csv = DEV / f"{name}.csv"
    assert csv.is_file(), f"the development logs belong beside the repository: no {csv}"
    bag = bags.write_bag(csv, tmp / name)
    mapping = tmp / f"{name}.toml"
    mapping.write_text(bags.mapping_for(bags.read_csv(csv)))
    return bag, mapping


def validate(exe: Path, out: Path, *args: str) -> subprocess.CompletedProcess:
    cmd = [str(exe), "validate", *args, "--dt", "0.02", "--quiet", "--no-plots", "--threads", "1",
           "--out", str(out)]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=900)


@pytest.mark.parametrize("name", list(case_params()))
def test_a_bag_gives_the_verdict_of_its_csv(shoal_bin, tmp_path, name):
    bag, mapping = bag_of(name, tmp_path)
    p = validate(shoal_bin, tmp_path / "out", str(bag), "--mapping", str(mapping))
    assert p.returncode == 0, p.stderr
    report = json.loads((tmp_path / "out" / "report.json").read_text())
    verdict = report["verdict"]
    assert sorted(verdict["effects"]) == sorted(PINNED_VERDICTS[name]), (
        f"{name}: the bag's verdict differs from the CSV's pinned one\n{p.stdout}"
    )
    forms, params = PINNED_FITS_BY_CASE[name]
    got = sorted(f"{e}/{f}" for e, f in zip(verdict["effects"], verdict["forms"]))
    assert got == forms, f"{name}: the bag's forms differ from the CSV's pinned ones"
    assert sorted(verdict["params"]) == sorted(params), name
    for k, want in params.items():
        assert abs(verdict["params"][k] - want) <= FIT_TOL * abs(want), (
            f"{name}: {k} = {verdict['params'][k]} from the bag, pinned {want} from the CSV")
    # The run was read from the bag (its ingest names the container and the topics), not from
    # a CSV beside it.
    (run,) = report["runs"]
    source = run["ingest"]["source"] or "(a CSV: no source)"
    assert source.startswith("rosbag2, 1 MCAP file(s)") and "/uauv2/" in source, source


@pytest.mark.parametrize("name", sorted(PINNED_VERDICTS))
def test_a_bags_run_is_its_csvs_row_by_row(tmp_path, name):
    """Without a search: the bag's run as `shoal validate` reads it, row by row, against the
    CSV the bag was written from (read here with numpy, and by shoal). Each row lies at a
    sample's header stamp (within the writer's jitter: a reader taking the log times, up to
    3.4 ms late, fails); each input is the CSV's command in force at the row's time (the
    last CSV sample at or before it: a command held a sample too long or too short fails);
    each channel sample is the CSV's value at the sample it was stamped from (a pressure
    converted with another g or density, a heading mirrored, a rate of the wrong sign fail),
    and no sample is missing or invented."""
    bag, mapping = bag_of(name, tmp_path)
    csv = DEV / f"{name}.csv"
    ref = bags.read_csv(csv)
    log = shoal.read_log(bag, mapping=mapping)
    text = shoal.read_log(csv)
    # The CSV's run is the file's numbers.
    assert list(text.columns) == list(ref), name
    for k, v in ref.items():
        np.testing.assert_array_equal(text.columns[k], v, err_msg=k)
    assert log.source.startswith(f"{len(log.t)} rows, rosbag2, 1 MCAP file(s)"), log.source
    t_csv = ref["t"]
    # Every input's first message is at the CSV's first time: the run starts there.
    t = t_csv[0] + log.t
    near = np.clip(np.searchsorted(t_csv, t), 1, len(t_csv) - 1)
    near = np.where(t - t_csv[near - 1] < t_csv[near] - t, near - 1, near)
    stamp_err = np.abs(t - t_csv[near])
    assert stamp_err.max() <= bags.JITTER_NS * 1e-9 + 1e-9, (
        f"{name}: a row {stamp_err.max() * 1e3:.3f} ms from every CSV sample")
    # The command in force: the last CSV row at or before the row's time (commands are
    # logged exactly at their rows' times; 1 ns of rounding in the stamps).
    held = np.searchsorted(t_csv, t + 1e-9, side="right") - 1
    inputs = [c for c in ref if c.startswith("u.")]
    assert sorted(c for c in log.columns if c.startswith("u.")) == sorted(inputs)
    for c in inputs:
        np.testing.assert_allclose(log.columns[c], ref[c][held], rtol=0, atol=1e-9,
                                   err_msg=f"{name}: {c}")
    channels = [c for c in ref if c.startswith("y.")]
    assert sorted(c for c in log.columns if c.startswith("y.")) == sorted(channels)
    late = t_csv >= t_csv[0] + bags.LATE_S - 1e-9
    for c in channels:
        rows = ~np.isnan(log.columns[c])
        k = near[rows]
        written = late & (np.arange(len(t_csv)) % 5 != 4 if c == "y.depth" else True)
        # One sample per written CSV sample, none twice.
        assert np.array_equal(np.sort(k), np.flatnonzero(written)), f"{name}: {c} samples"
        got, want = log.columns[c][rows], ref[c][k]
        diff = np.angle(np.exp(1j * (got - want))) if c == "y.yaw" else got - want
        assert np.abs(diff).max() <= 1e-9, (
            f"{name}: {c} differs by {np.abs(diff).max():.3g} from the CSV's samples")


def test_the_bag_holds_what_a_ros2_logger_writes(tmp_path):
    """The bag is what the test claims: its own rates, jitter, a late topic, a vendor type."""
    from mcap.reader import make_reader

    bag, _ = bag_of("dev_y_gain", tmp_path)
    (mcap_file,) = sorted(bag.glob("*.mcap"))
    times = {}
    schemas = {}
    with open(mcap_file, "rb") as f:
        for schema, channel, message in make_reader(f).iter_messages():
            times.setdefault(channel.topic, []).append(message.log_time)
            schemas[channel.topic] = (schema.name, schema.encoding, channel.message_encoding)
    assert schemas["/uauv2/pump"] == ("uauv2_msgs/msg/Pump", "ros2msg", "cdr")
    assert schemas["/uauv2/imu"][0] == "sensor_msgs/msg/Imu"
    csv_rows = len(bags.read_csv(DEV / "dev_y_gain.csv")["t"])
    # The IMU starts late; the commands only on change (far fewer than the rows).
    assert len(times["/uauv2/imu"]) == csv_rows - int(bags.LATE_S * 50)
    assert len(times["/uauv2/thrusters"]) < csv_rows / 4
    assert min(times["/uauv2/imu"]) > min(times["/uauv2/thrusters"]) + 0.3e9


def test_bad_bags_and_mappings_are_named(shoal_bin, tmp_path):
    bag, mapping = bag_of("dev_h_lag2", tmp_path)
    text = mapping.read_text()

    def fails(*args, want):
        p = validate(shoal_bin, tmp_path / "o", *args)
        assert p.returncode == 2, (args, p.returncode, p.stderr)
        assert want in p.stderr, (want, p.stderr)
        assert "panicked" not in p.stderr

    # No mapping.
    fails(str(bag), want="needs a mapping file")
    # A topic the bag does not have.
    m = tmp_path / "topic.toml"
    m.write_text(text.replace("/uauv2/tilts", "/uauv2/tilt"))
    fails(str(bag), "--mapping", str(m), want="topic `/uauv2/tilt` has no messages")
    # A field path that does not exist names the type's fields.
    m = tmp_path / "field.toml"
    m.write_text(text.replace('field = "fluid_pressure"', 'field = "pressure"'))
    fails(str(bag), "--mapping", str(m),
          want="`pressure` is not a field of sensor_msgs/FluidPressure (its fields: header, "
               "fluid_pressure, variance)")
    # An index past the end of a sequence names the message.
    m = tmp_path / "index.toml"
    m.write_text(text.replace('"data[2]"', '"data[3]"'))
    fails(str(bag), "--mapping", str(m), want="topic `/uauv2/thrusters`, message 1: std_msgs/msg/Float64MultiArray : `data[3]` is past the end of `data`: index 3")
    # A typo in the mapping file.
    m = tmp_path / "typo.toml"
    m.write_text(text.replace("topic =", "topik =", 1))
    fails(str(bag), "--mapping", str(m), want="unknown field `topik`")
    # A truncated bag.
    (mcap_file,) = sorted(bag.glob("*.mcap"))
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(mcap_file.read_bytes()[: mcap_file.stat().st_size // 2])
    fails(str(cut), "--mapping", str(mapping), want="breaks off")
    # Not an MCAP file.
    junk = tmp_path / "junk.mcap"
    junk.write_bytes(b"not a bag at all")
    fails(str(junk), "--mapping", str(mapping), want="not an MCAP file")


def test_a_topic_without_a_schema_is_named(shoal_bin, tmp_path):
    """A channel written without a message definition (schema id 0) cannot be decoded."""
    from mcap.writer import Writer

    path = tmp_path / "noschema.mcap"
    with open(path, "wb") as f:
        w = Writer(f)
        w.start(profile="ros2")
        ch = w.register_channel(topic="/p", message_encoding="cdr", schema_id=0)
        for k in range(3):
            w.add_message(ch, log_time=k * 10**8, data=b"\0\1\0\0" + bytes(24), publish_time=k * 10**8)
        w.finish()
    mapping = tmp_path / "m.toml"
    mapping.write_text('[channels]\n"y.depth" = { topic = "/p", field = "fluid_pressure" }\n')
    p = validate(shoal_bin, tmp_path / "o", str(path), "--mapping", str(mapping))
    assert p.returncode == 2, p.stderr
    assert "topic `/p`: the channel has no schema" in p.stderr, p.stderr


def test_a_runs_mcap_gives_the_verdict_of_its_csv(shoal_bin, tmp_path):
    """Round trip: `shoal run --mcap` of a μAUV² diving with a thruster lag hidden in its model;
    the file's ROS 2 topics read through the shipped mapping give the verdict — effects, forms,
    parameters, per-channel table — of the same run written as a CSV from trajectories.csv."""
    import csv

    world = (REPO / "worlds" / "paper_diving.toml").read_text().replace(
        "[output]",
        '[[vehicles.model.effects]]\nname = "thruster_lag"\nparams = { tau_s = 0.4 }\n\n[output]',
    )
    (tmp_path / "lag_dive.toml").write_text(world)
    run = tmp_path / "run"
    p = subprocess.run([str(shoal_bin), "run", str(tmp_path / "lag_dive.toml"), "--mcap", "--quiet",
                        "--no-plots", "--no-replay", "--out", str(run)],
                       capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stderr
    rows = list(csv.DictReader(open(run / "trajectories.csv")))
    # The tilts' inputs are the commanded angles (run.mcap's `tilts`), as a logger records
    # what it sent the drives; the drives' own lag is the model's.
    cols = ["t_s", "cmd_top_pct", "cmd_port_pct", "cmd_stbd_pct", "cmd_alpha_rad",
            "cmd_beta_rad", "pump", "depth_reading_m"]
    # A row's commands are those of the interval ending at its time; run.mcap stamps them
    # when they came into force (the sample before), and so does this CSV.
    with open(tmp_path / "run.csv", "w") as f:
        f.write("t,u.top,u.port,u.stbd,u.alpha,u.beta,u.pump,y.depth\n")
        for k, r in enumerate(rows):
            nxt = rows[min(k + 1, len(rows) - 1)]
            vals = [r["t_s"]] + [nxt[c] for c in cols[1:-1]] + [r["depth_reading_m"]]
            f.write(",".join(vals) + "\n")
    mapping = REPO / "examples" / "rosbag2" / "uauv2_run.toml"
    reports = []
    for src, out in [(run / "run.mcap", "v_mcap"), (tmp_path / "run.csv", "v_csv")]:
        p = subprocess.run([str(shoal_bin), "validate", str(src), "--mapping", str(mapping),
                            "--quiet", "--no-plots", "--threads", "1", "--out", str(tmp_path / out)],
                           capture_output=True, text=True, timeout=900)
        assert p.returncode == 0, p.stderr
        reports.append(json.loads((tmp_path / out / "report.json").read_text())["verdict"])
    bag, text = reports
    assert bag["effects"] == text["effects"] == ["thruster_lag"], (bag["summary"], text["summary"])
    assert bag["forms"] == text["forms"]
    # The CSV holds trajectories.csv's numbers (7 significant digits), the MCAP the f64 values
    # themselves: the fits agree to that rounding (measured: 2e-6 relative on the RMSE).
    for k, v in text["params"].items():
        assert bag["params"][k] == pytest.approx(v, rel=1e-4), k
    for ch, row in text["channels"].items():
        assert bag["channels"][ch]["rmse_after"] == pytest.approx(row["rmse_after"], rel=1e-4)
        assert bag["channels"][ch]["rmse_before"] == pytest.approx(row["rmse_before"], rel=1e-4)


MAPPINGS = REPO / "examples" / "rosbag2"


def test_every_shipped_mapping_names_a_bag_that_exists_or_a_documented_command_writes(
        tmp_path):
    """Each `examples/rosbag2/*.toml` shows `shoal validate BAG --mapping <itself>`; BAG is in
    the repository, or the run directory of a `shoal run --mcap --out DIR` shown before it
    (DIR/run.mcap), or what a script shown before it writes (`… SCRIPT.py BAG`) — which is run
    here, and its bag read through the mapping."""
    seen = 0
    for mapping in sorted(MAPPINGS.glob("*.toml")):
        comments = "\n".join(l[1:].strip() for l in mapping.read_text().splitlines()
                             if l.startswith("#")).replace("\\\n", " ")
        rel = f"examples/rosbag2/{mapping.name}"
        m = re.search(r"shoal validate (\S+) --mapping " + re.escape(rel), comments)
        assert m, f"{mapping.name}: no `shoal validate BAG --mapping {rel}` in its comments"
        bag = m.group(1)
        before = comments[: m.start()]
        run = re.search(r"shoal run (\S+) --mcap --out (\S+)", before)
        script = re.search(r"(examples/\S+\.py) " + re.escape(bag) + r"\b", before)
        if (REPO / bag).exists():
            pass
        elif run and f"{run.group(2)}/run.mcap" == bag:
            assert (REPO / run.group(1)).is_file(), f"{mapping.name}: no world {run.group(1)}"
        elif script:
            written = tmp_path / Path(bag).name
            subprocess.run([sys.executable, REPO / script.group(1), written], check=True,
                           capture_output=True, text=True, timeout=600)
            vehicle = re.search(r"--vehicle (\S+)", comments[m.start():])
            r = shoal.validate(written, mapping=mapping, effects="thrust_gain", dt=0.02,
                               threads=1, quiet=True,
                               vehicle=REPO / vehicle.group(1) if vehicle else None)
            assert r.data["runs"], r.data
        else:
            raise AssertionError(f"{mapping.name}: `{bag}` exists nowhere and no command "
                                 "shown before writes it")
        seen += 1
    assert seen >= 2


def test_the_documented_round_trip_explains_a_runs_own_mcap(shoal_bin, tmp_path):
    """docs/mcap.md's round trip — `shoal run worlds/paper_diving.toml --mcap`, then
    `shoal validate run.mcap --mapping examples/rosbag2/uauv2_run.toml` — gives an empty
    verdict: the model that made the run explains it, with no unexplained structure. (The
    `tilts` topic carried the drives' true angles, which the mapping feeds in as commands,
    and every command was stamped at the end of the control period it acted in, so the
    replay applied it 50 ms late: y.depth kept a structure 2.2× the noise floor.)"""
    run = tmp_path / "dive"
    p = subprocess.run([str(shoal_bin), "run", str(REPO / "worlds" / "paper_diving.toml"),
                        "--mcap", "--quiet", "--no-plots", "--no-replay", "--out", str(run)],
                       capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stderr
    mapping = REPO / "examples" / "rosbag2" / "uauv2_run.toml"
    out = tmp_path / "v"
    p = subprocess.run([str(shoal_bin), "validate", str(run / "run.mcap"), "--mapping",
                        str(mapping), "--quiet", "--no-plots", "--out", str(out)],
                       capture_output=True, text=True, timeout=1200)
    assert p.returncode == 0, p.stderr
    verdict = json.loads((out / "report.json").read_text())["verdict"]
    assert verdict["effects"] == [], verdict["summary"]
    assert verdict["unexplained"] == [], verdict["summary"]
