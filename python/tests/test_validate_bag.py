"""``shoal.validate`` reads rosbag2s through ``mapping=`` as ``shoal validate --mapping`` does
(one reader seam, shoal_sysid::log::readers): a development log recorded as a ROS 2 logger
records it (``rosbag_writer.py``) gives Python the command line's verdict and table; a bag
given without a mapping is recognised by its content and the error says a mapping is needed;
`shoal.read_log` reads logs through the same readers and raises their errors, and returns a
log's references (`r.` columns) beside its inputs and measurements;
progress goes to stderr unless ``quiet``; and Ctrl-C interrupts a validation at once."""

import json
import signal
import subprocess
import sys
import time

import pytest

import shoal
from conftest import REPO, interruptible
from test_rosbag import bag_of

DEV = REPO.parent / "shared" / "data" / "validation_dev"
ONLY = "thrust_gain,damping_error"


def test_python_reads_a_bag_through_its_mapping_as_the_command_line(shoal_bin, tmp_path):
    bag, mapping = bag_of("dev_y_gain", tmp_path)
    r = shoal.validate(bag, mapping=mapping, dt=0.02, threads=1, effects=ONLY, quiet=True)
    out = tmp_path / "cli"
    p = subprocess.run(
        [str(shoal_bin), "validate", str(bag), "--mapping", str(mapping), "--dt", "0.02",
         "--threads", "1", "--effects", ONLY, "--quiet", "--no-plots", "--out", str(out)],
        capture_output=True, text=True, timeout=900,
    )
    assert p.returncode == 0, p.stderr
    cli = json.loads((out / "report.json").read_text())
    assert r.data["verdict"] == cli["verdict"]
    assert r.effect_names == ["thrust_gain"]
    for name, ch in r.channels.items():
        want = cli["verdict"]["channels"][name]["rmse_before"]
        assert ch.rmse_before == pytest.approx(want, rel=1e-12), name


def test_a_bag_without_a_mapping_is_recognised_by_content(tmp_path):
    bag, _ = bag_of("dev_y_gain", tmp_path)
    mcaps = sorted(bag.glob("*.mcap")) if bag.is_dir() else [bag]
    for path in [bag, *mcaps]:
        with pytest.raises(shoal.ValidationError) as e:
            shoal.validate(path, quiet=True)
        msg = str(e.value)
        assert "needs a mapping file" in msg and 'mapping="MAPPING.toml"' in msg, msg
        assert "UTF-8" not in msg, msg


def test_a_bad_mapping_names_the_setting_and_file(tmp_path):
    bag, mapping = bag_of("dev_y_gain", tmp_path)
    text = mapping.read_text()
    assert '"y.yaw"' in text
    mapping.write_text(text.replace('"y.yaw"', '"y.yew"'))
    with pytest.raises(shoal.ValidationError) as e:
        shoal.validate(bag, mapping=mapping, quiet=True)
    assert e.value.setting == "mapping" and e.value.file == mapping, str(e.value)
    assert "did you mean `y.yaw`?" in str(e.value)


def test_progress_goes_to_stderr_unless_quiet(capfd):
    log = DEV / "dev_y_gain.csv"
    shoal.validate(log, dt=0.02, threads=1, effects="thrust_gain")
    err = capfd.readouterr().err
    assert f"shoal: read {log}: " in err, err
    assert "shoal: validating `" in err, err
    shoal.validate(log, dt=0.02, threads=1, effects="thrust_gain", quiet=True)
    assert capfd.readouterr().err == ""
    heard = []
    shoal.validate(log, dt=0.02, threads=1, effects="thrust_gain",
                   progress=lambda k, m: heard.append(k))
    assert capfd.readouterr().err == "" and "start" in heard and "fit" in heard


def test_ctrl_c_interrupts_a_validation_at_once(tmp_path):
    # The whole catalogue on one thread: about a minute of search.
    script = (
        "import shoal, sys\n"
        f"shoal.validate({str(DEV / 'dev_y_gain.csv')!r}, threads=1, quiet=True)\n"
        "print('finished')\n"
    )
    p = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True, preexec_fn=interruptible)
    time.sleep(3.0)
    assert p.poll() is None, p.communicate()
    sent = time.monotonic()
    p.send_signal(signal.SIGINT)
    out, err = p.communicate(timeout=60)
    waited = time.monotonic() - sent
    assert "KeyboardInterrupt" in err, err
    assert "finished" not in out
    assert waited < 2.0, f"{waited:.1f} s from Ctrl-C to the exception"


def test_read_log_names_what_it_cannot_read(tmp_path):
    """`shoal.read_log` reads through the validation's readers, so its errors are theirs: a
    bad mapping names the setting and the file, a broken CSV row its file, line and column,
    a bag without a mapping says a mapping is needed."""
    bag, mapping = bag_of("dev_y_gain", tmp_path)
    bad = tmp_path / "bad.toml"
    bad.write_text(mapping.read_text().replace('"y.yaw"', '"y.yew"'))
    with pytest.raises(shoal.ValidationError) as e:
        shoal.read_log(bag, mapping=bad)
    assert e.value.setting == "mapping" and e.value.file == bad, str(e.value)
    with pytest.raises(shoal.ValidationError) as e:
        shoal.read_log(bag)
    assert "needs a mapping file" in str(e.value)
    csv = tmp_path / "broken.csv"
    csv.write_text("t,u.top,y.depth\n0,0,0.5\n0.02,zero,0.5\n")
    with pytest.raises(shoal.ValidationError) as e:
        shoal.read_log(csv)
    assert (e.value.file, e.value.line, e.value.column) == (csv, 3, "u.top"), str(e.value)
    # A readable one: the columns of the file, the time from its first row.
    csv.write_text("t,u.top,y.depth\n1.0,5,0.5\n1.02,,\n1.04,7,0.52\n")
    log = shoal.read_log(csv)
    assert list(log.columns) == ["t", "u.top", "y.depth"]
    assert log.columns["u.top"].tolist() == [5.0, 5.0, 7.0]
    t, depth = log.samples("y.depth")
    assert t.tolist() == [1.0, 1.04] and depth.tolist() == [0.5, 0.52]


def test_read_log_returns_the_references_held_as_the_inputs(tmp_path):
    """`r.` columns come back beside `u.` and `y.`, each the value in force at every row (an
    empty cell holds it, rows before the first value take that value), the mode as its code
    (diving 1, auto 5, turning 3), whether written by name or by code."""
    csv = tmp_path / "mission.csv"
    csv.write_text(
        "t,u.top,y.depth,r.depth,r.mode\n"
        "0,5,0.5,,diving\n"
        "0.1,,0.5,1.5,\n"
        "0.2,,0.6,,AUTO\n"
        "0.3,,0.6,2,3\n"
    )
    log = shoal.read_log(csv)
    assert list(log.columns) == ["t", "u.top", "y.depth", "r.depth", "r.mode"]
    assert log.columns["r.depth"].tolist() == [1.5, 1.5, 1.5, 2.0]
    assert log.columns["r.mode"].tolist() == [1.0, 1.0, 5.0, 3.0]
    assert log.columns["u.top"].tolist() == [5.0] * 4
