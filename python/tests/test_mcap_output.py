"""`shoal run --mcap` writes `run.mcap` for Foxglove and ROS 2 tools: read back with PyPI's
`mcap` (and its ROS 2 decoder, `mcap-ros2-support`) and with `rosbags`' `AnyReader`, neither
of which knows anything of shoal: the ROS 2 profile, the schemas by name and encoding, one
message per recorded sample and vehicle on every per-vehicle topic and one per reception
attempt, log times in order, every message decoded by the definitions in the file and equal
to the trajectories (pressure from the depth reading, ENU/FLU attitude with its sign, and
body axes pointing where a turning vehicle heads, by hand), and
the summary's account of the file."""

import csv
import json
import math
import resource
import subprocess
from collections import Counter, defaultdict

from rosbags.highlevel import AnyReader
import pytest
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory
from shoal_ros2 import enu

from conftest import WORLDS, shoal_run

#: The last parts of each vehicle's topics.
VEHICLE_TOPICS = ["state", "pressure", "imu", "thrusters", "tilts", "tilt_angles", "pump"]


@pytest.fixture(scope="module")
def run(shoal_bin, tmp_path_factory):
    """The default world (12 μAUV², beacons, a pillar) for 3 s with `--mcap`: the output
    folder, its summary, the trajectory rows by vehicle and every message of run.mcap."""
    out = tmp_path_factory.mktemp("mcap")
    summary = shoal_run(shoal_bin, WORLDS / "default.toml", out, "--mcap", "--duration", "3")
    with open(out / "vehicles.csv", newline="") as f:
        vehicles = [r["name"] for r in csv.DictReader(f)]
    rows = defaultdict(list)
    with open(out / "trajectories.csv", newline="") as f:
        for r in csv.DictReader(f):
            rows[r["vehicle"]].append(r)
    messages = []
    with open(out / "run.mcap", "rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        for schema, channel, message, msg in reader.iter_decoded_messages(log_time_order=False):
            messages.append((schema, channel, message, msg))
    return out, summary, vehicles, rows, messages


def on(messages, topic):
    return [m for m in messages if m[1].topic == topic]


def test_every_topic_has_a_message_per_sample_and_vehicle(run):
    _, summary, vehicles, rows, messages = run
    assert len(vehicles) == 12
    samples = len(rows[vehicles[0]])
    assert samples == 31 and summary["trajectory_rows"] == samples * len(vehicles)
    counts = Counter(c.topic for _, c, _, _ in messages)
    for v in vehicles:
        for t in VEHICLE_TOPICS:
            assert counts[f"/{v}/{t}"] == samples, (v, t)
    assert counts["/tf"] == samples
    assert counts["/scene"] == 1
    attempts = summary["comm"]["receptions"]["attempts"]
    assert attempts > 100
    assert counts["/optical/frames"] == attempts
    lines = sum(len(d.entities) for _, _, _, d in on(messages, "/links"))
    assert lines == attempts
    assert len(counts) == 4 + 7 * len(vehicles)
    m = summary["mcap"]
    assert (m["messages"], m["samples_written"], m["frames_written"]) == (len(messages), samples, attempts)


def test_log_times_are_simulated_time_in_order(run):
    _, _, vehicles, rows, messages = run
    times = [m.log_time for _, _, m, _ in messages]
    assert times == sorted(times)
    assert all(m.publish_time == m.log_time for _, _, m, _ in messages)
    tf = [m.log_time for _, _, m, _ in on(messages, "/tf")]
    assert tf == [round(float(r["t_s"]) * 1e9) for r in rows[vehicles[0]]]
    assert tf[-1] == 3_000_000_000


def test_schemas_are_ros_2_definitions_and_every_message_cdr(run):
    out, _, _, _, messages = run
    with open(out / "run.mcap", "rb") as f:
        assert make_reader(f).get_header().profile == "ros2"
    kinds = {c.topic: (s.name, s.encoding, c.message_encoding) for s, c, _, _ in messages}
    assert kinds["/tf"] == ("tf2_msgs/msg/TFMessage", "ros2msg", "cdr")
    assert kinds["/scene"] == ("foxglove_msgs/msg/SceneUpdate", "ros2msg", "cdr")
    assert kinds["/links"] == ("foxglove_msgs/msg/SceneUpdate", "ros2msg", "cdr")
    assert kinds["/optical/frames"] == ("shoal_msgs/msg/ReceptionAttempt", "ros2msg", "cdr")
    assert kinds["/west-0/state"] == ("shoal_msgs/msg/VehicleState", "ros2msg", "cdr")
    assert kinds["/west-0/pressure"] == ("sensor_msgs/msg/FluidPressure", "ros2msg", "cdr")
    assert kinds["/west-0/imu"] == ("sensor_msgs/msg/Imu", "ros2msg", "cdr")
    for t in ["thrusters", "tilts", "pump"]:
        assert kinds[f"/east-3/{t}"] == ("std_msgs/msg/Float64MultiArray", "ros2msg", "cdr")
    assert {e for _, e, _ in kinds.values()} == {"ros2msg"}
    # Every field of a state has its unit in the definition.
    state = next(s for s, _, _, _ in messages if s.name == "shoal_msgs/msg/VehicleState")
    text = state.data.decode()
    assert "float64 depth_reading_m # the pressure sensor's depth reading" in text
    assert "float64 q_rad_s # pitch rate about body y (FRD) [rad/s]" in text


def test_rosbags_any_reader_reads_every_topic_as_the_trajectories(run):
    """The ROS 2 profile, as a rosbag2 reader checks it: `rosbags`' AnyReader opens the file
    (it refuses any other profile and any non-ROS 2 schema), registers the types from the
    file's definitions and decodes every message; the states equal the trajectory rows."""
    out, summary, vehicles, rows, messages = run
    counts = Counter()
    states = defaultdict(list)
    with AnyReader([out / "run.mcap"]) as reader:
        for conn, _, raw in reader.messages():
            msg = reader.deserialize(raw, conn.msgtype)
            counts[conn.topic] += 1
            if conn.topic.endswith("/state"):
                states[conn.topic.split("/")[1]].append(msg)
    assert counts == Counter(c.topic for _, c, _, _ in messages)
    for v in vehicles:
        assert len(states[v]) == len(rows[v])
        for st, row in zip(states[v], rows[v]):
            assert st.mode == row["mode"]
            for name in ["t_s", "x_m", "z_m", "yaw_rad", "depth_reading_m", "ballast_m3"]:
                # trajectories.csv keeps 7 significant digits, the file the f64 itself.
                assert math.isclose(getattr(st, name), float(row[name]), rel_tol=1e-6,
                                    abs_tol=1e-9), (v, name)


def test_ros_2_messages_are_the_recorded_values_in_enu(run):
    out, _, vehicles, rows, _ = run
    decoded = defaultdict(list)
    with open(out / "run.mcap", "rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        topics = [f"/{v}/{t}" for v in vehicles for t in ["pressure", "imu", "thrusters", "pump"]]
        for _, channel, message, msg in reader.iter_decoded_messages(topics=topics):
            decoded[channel.topic].append((message, msg))
    rel = {"rel_tol": 1e-6, "abs_tol": 1e-6}
    for v in vehicles:
        for k, row in enumerate(rows[v]):
            t_ns = round(float(row["t_s"]) * 1e9)
            _, p = decoded[f"/{v}/pressure"][k]
            assert (p.header.stamp.sec * 10**9 + p.header.stamp.nanosec) == t_ns
            assert p.header.frame_id == v
            # 101325 Pa + ρ g · depth reading, with the default world's 1000 kg/m³ and 9.81 m/s².
            want = 101325.0 + 1000.0 * 9.81 * float(row["depth_reading_m"])
            assert math.isclose(p.fluid_pressure, want, rel_tol=1e-9, abs_tol=0.01)
            _, imu = decoded[f"/{v}/imu"][k]
            yaw = float(row["yaw_rad"])
            # Python's one NED→ENU (shoal_ros2.enu) of the row's attitude. q and −q are the
            # same rotation: |q · q_want| = 1 (a mirrored heading −yaw gives less).
            want_q = enu.attitude_from_ned(float(row["roll_rad"]), float(row["pitch_rad"]), yaw)
            o = imu.orientation
            dot = o.x * want_q.x + o.y * want_q.y + o.z * want_q.z + o.w * want_q.w
            assert math.isclose(abs(dot), 1.0, abs_tol=1e-9), (v, k, o, want_q)
            assert math.isclose(imu.angular_velocity.z, -float(row["r_rad_s"]), **rel)
            assert imu.linear_acceleration_covariance[0] == -1.0
            # Commands are stamped when they came into force: the next row's (which holds
            # the interval ending there); the last sample's are its own.
            nxt = rows[v][min(k + 1, len(rows[v]) - 1)]
            _, thr = decoded[f"/{v}/thrusters"][k]
            assert thr.layout.dim[0].label == "top,port,stbd"
            for name, x in zip(["top", "port", "stbd"], thr.data):
                assert math.isclose(x, float(nxt[f"cmd_{name}_pct"]), **rel)
            _, pump = decoded[f"/{v}/pump"][k]
            assert list(pump.data) == [float(nxt["pump"])]


def test_tf_places_every_vehicle_east_north_up(run):
    _, _, vehicles, rows, messages = run
    for k, (_, _, _, m) in enumerate(on(messages, "/tf")):
        assert [t.child_frame_id for t in m.transforms] == vehicles
        for t, v in zip(m.transforms, vehicles):
            row = rows[v][k]
            assert t.header.frame_id == "world"
            tr = t.transform.translation
            got = [tr.x, tr.y, tr.z]
            want = [float(row["y_m"]), float(row["x_m"]), -float(row["z_m"])]
            assert all(math.isclose(a, b, rel_tol=1e-6, abs_tol=1e-6) for a, b in zip(got, want))


def body_axes(q):
    """Forward and up body axes (FLU x and z) of the unit quaternion `q` in ENU."""
    x, y, z, w = q.x, q.y, q.z, q.w
    forward = (1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y))
    up = (2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y))
    return forward, up


def want_axes(row):
    """The same axes by hand from the row's NED/FRD roll φ, pitch θ and yaw ψ (REP 103):
    forward (sin ψ cos θ, cos ψ cos θ, sin θ) in (east, north, up); up FRD's −z."""
    phi, theta, psi = (float(row[c]) for c in ["roll_rad", "pitch_rad", "yaw_rad"])
    a = math.cos(psi) * math.sin(theta) * math.cos(phi) + math.sin(psi) * math.sin(phi)
    b = math.sin(psi) * math.sin(theta) * math.cos(phi) - math.cos(psi) * math.sin(phi)
    forward = (math.sin(psi) * math.cos(theta), math.cos(psi) * math.cos(theta), math.sin(theta))
    return forward, (-b, -a, math.cos(theta) * math.cos(phi))


def test_imu_and_tf_point_the_vehicle_where_it_heads(shoal_bin, tmp_path):
    """worlds/paper_turning.toml turns from north through east to south and back to 45°:
    headings whose mirror, north–east swap and ENU angle all differ from them (the default
    world's 0° and 180° are blind to a mirrored heading). Each sample's IMU orientation and
    /tf rotation, turned into body axes, point where the row's roll, pitch and yaw say — by
    hand, not through shoal_ros2.enu."""
    summary = shoal_run(shoal_bin, WORLDS / "paper_turning.toml", tmp_path, "--mcap",
                        "--duration", "30")
    assert summary["mcap"]["messages"] > 0
    with open(tmp_path / "trajectories.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    (name,) = {r["vehicle"] for r in rows}
    yaws = [float(r["yaw_rad"]) for r in rows]
    assert any(abs(math.sin(y)) > 0.5 and abs(math.cos(y)) > 0.5 for y in yaws), "no diagonal heading"
    got = defaultdict(list)
    with open(tmp_path / "run.mcap", "rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        for _, channel, _, msg in reader.iter_decoded_messages(topics=[f"/{name}/imu", "/tf"]):
            q = msg.orientation if channel.topic.endswith("imu") else msg.transforms[0].transform.rotation
            got[channel.topic].append(body_axes(q))
    for topic, axes in got.items():
        assert len(axes) == len(rows), topic
        for k, ((fwd, up), row) in enumerate(zip(axes, rows)):
            want_fwd, want_up = want_axes(row)
            # trajectories.csv keeps 7 significant digits.
            assert all(math.isclose(a, b, abs_tol=1e-6) for a, b in zip(fwd + up, want_fwd + want_up)), (
                topic, k, row["t_s"], fwd, up, want_fwd, want_up)


def test_the_summary_lists_run_mcap(run):
    out, summary, _, _, _ = run
    assert str(out / "run.mcap") in summary["files"]
    m = summary["mcap"]
    assert m["bytes"] == (out / "run.mcap").stat().st_size
    assert m["sample_every"] == 1 and m["vehicles"] == m["vehicles_in_world"] == 12
    assert not any(p.name.startswith(".") for p in out.iterdir()), "no temporaries left"


def test_a_file_size_limit_names_run_mcap_and_leaves_no_partial_file(shoal_bin, tmp_path):
    """A full disk, as a file-size limit: run.mcap (held in memory until its chunk is whole)
    is the file that breaks it; the error names it, exit code 1, no truncated file or
    temporary under the folder, and the summary says what exists."""
    world = tmp_path / "w.toml"
    world.write_text(
        'name = "limited"\nduration = 2.0\n[pool]\nsize = [10.0, 10.0, 3.0]\n'
        '[[vehicles]]\nname = "auv"\nposition = [5.0, 5.0, 0.5]\n'
        'mission = [{ t = 0, mode = "auto", depth = 1.0, yaw_deg = 0 }]\n'
    )
    out = tmp_path / "out"

    def limit():
        resource.setrlimit(resource.RLIMIT_FSIZE, (20_000, 20_000))

    p = subprocess.run(
        [str(shoal_bin), "run", str(world), "--quiet", "--mcap", "--no-replay", "--no-plots",
         "--out", str(out)],
        capture_output=True, text=True, timeout=120, preexec_fn=limit,
    )
    assert p.returncode == 1, p.stderr
    assert f"error: cannot write {out / 'run.mcap'}: File too large" in p.stderr
    names = sorted(f.name for f in out.iterdir())
    assert names == ["summary.json", "trajectories.csv", "vehicles.csv"]
    s = json.loads((out / "summary.json").read_text())
    assert "run.mcap" in s["output_error"] and "mcap" not in s
