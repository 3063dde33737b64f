"""shoal's ROS 2 bridge against `shoal run` in lock-step: 2 μAUV² with `agent = "ros2"` beside
`ros2_agent.py` (package `shoal_ros2` on Cyclone DDS), each test on its own namespace and DDS
domain, DDS on the loopback (`localhost_dds`).

* The Imu and FluidPressure the agent receives are the run's own trajectories.csv: in sea water
  (`[water] density = 1025`) the raw FluidPressure is 101325 Pa + ρ g × the depth reading by
  hand, and with the centre of gravity moved off the centre line (the vehicles swing in roll
  and pitch) roll, pitch, p and q, far from 0, are the run's within the IMU's noise; yaw and r
  while turning to the setpoints.
* The vehicles reach the depth and heading sent as setpoints; raw Actuators drive the thrusters
  and tilts, and with positions granted `odom` is the true position; a NaN depth and an unknown
  mode are counted as rejections and not applied; two runs give the same digest; and
  `python/examples/ros2_school.py` aligns the school of worlds/ros2_school.toml with beacons
  over modem/tx and modem/rx.
* An agent killed mid-run (between two ticks, or after answering one of the vehicles) leaves
  both vehicles to the fallback from the tick it missed, as the run recorded it, and the run
  ends cleanly.
* Unicasts (four vehicles, `UNICAST_WORLD`): an acknowledged one reaches its destination's
  `modem/rx` alone, naming its sender, and its sender's `modem/outcome` says acknowledged with
  its tag; one to a vehicle that hears nothing is given up after 1 + `arq_retries`
  transmissions, at the time the world's `ack_timeout` makes by hand; frames to no vehicle or
  to the sender itself are counted as bad frames.

Counted in ticks, not wall time: the agent leaves after answering the run's last tick, and
every tick is asserted answered once, in order. The world's lock-step `timeout` (wall time, the
only way a world tells a dead agent from a slow one) is generous everywhere; the killed-agent
test needs it to pass once and runs its two cases side by side.
"""

import csv
import json
import math
import signal
import subprocess
import sys
import time
from collections import defaultdict
from pathlib import Path

import pytest

from conftest import REPO, WORLDS, bus
from shoal_ros2 import Ros2Swarm, Setpoint, ros_name

HERE = Path(__file__).resolve().parent
AGENT = HERE / "ros2_agent.py"
EXAMPLES = REPO / "python" / "examples"

#: The test world's IMU noise (stated in `world` below): attitude [rad] and rates [rad/s],
#: standard deviations per axis.
ATTITUDE_NOISE = math.radians(0.5)
GYRO_NOISE = 0.01
#: Agreement demanded of a noisy reading with the truth: this many standard deviations.
SIGMAS = 6.0
#: Control period of the μAUV² [s].
TICK = 0.05
#: The world's wait for an agent's answer to a tick [s, wall time]: long enough never to run
#: out on a loaded machine (a dead agent is the killed-agent test's business).
TIMEOUT = 60.0


#: The test world's vehicles: two μAUV² at 0.8 m heading north, 4 m apart, with the IMU
#: noise above.
AUV_PAIR = f"""
[[vehicles]]
name = "auv"
count = 2
grid = {{ origin = [3.0, 4.5, 0.8], spacing = [4.0, 4.0], columns = 2 }}
agent = "ros2"

[vehicles.model.imu]
attitude_noise_deg = {math.degrees(ATTITUDE_NOISE)}
gyro_noise = {GYRO_NOISE}
gyro_bias = [0.0, 0.0, 0.0]
accel_noise = 0.02
"""


def world(namespace, domain, *, duration, fallback="hold", timeout=TIMEOUT, seed=5,
          grant_position=False, extra="", vehicles=AUV_PAIR):
    """`vehicles` (TOML; default `AUV_PAIR`) driven over ROS 2 in lock-step; `extra`: TOML
    appended (tables for the last vehicle group's model, `[water]`)."""
    return f"""
name = "ros2_test"
seed = {seed}
duration = {duration}
dt = 0.01

[pool]
size = [10.0, 10.0, 3.0]

[agents]
timing = "lockstep"
timeout = {timeout}
attach_timeout = 60.0
fallback = "{fallback}"
grant_position = {str(grant_position).lower()}

[ros2]
domain_id = {domain}
namespace = "{namespace}"
{vehicles}{extra}
[output]
record_hz = 10.0
"""


#: The test world's vehicle names, as trajectories.csv has them (topics: auv_0, auv_1).
VEHICLES = ["auv-0", "auv-1"]


@pytest.fixture(scope="session")
def ros2_shoal(shoal_bin, tmp_path_factory, localhost_dds):
    """The `shoal` binary, once it is known to bridge a world to ROS 2: it accepts a world
    with `agent = "ros2"` and `[ros2]`, and running it, publishes a first tick that a
    `Ros2Swarm` here receives (waited for up to 30 s). Else every test that needs it fails
    saying so (the bridge, crates/shoal-ros2, is not in this binary)."""
    tmp = tmp_path_factory.mktemp("ros2probe")
    namespace, domain = bus()
    path = tmp / "w.toml"
    path.write_text(world(namespace, domain, duration=0.2))
    p = subprocess.run([str(shoal_bin), "check", str(path)], capture_output=True, text=True,
                       timeout=60)
    if p.returncode != 0:
        pytest.fail(f"{shoal_bin} has no ROS 2 bridge: `shoal check` refuses a world with "
                    f"agent = \"ros2\" and a [ros2] table:\n{p.stdout}{p.stderr}", pytrace=False)
    with Ros2Swarm(namespace, VEHICLES, domain) as swarm:
        sim = subprocess.Popen([str(shoal_bin), "run", str(path), "--quiet", "--no-plots",
                                "--no-replay", "--out", str(tmp / "out")],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        try:
            tick = swarm.wait_tick(30.0)
            if tick is not None:
                for v in VEHICLES:
                    swarm.send_setpoint(v, tick.stamp, Setpoint.MODE_KEEP, 0.0, 0.0)
        finally:
            sim.kill()
            _, err = sim.communicate()
    if tick is None:
        pytest.fail(f"{shoal_bin} has no ROS 2 bridge: running a world with agent = \"ros2\" "
                    f"(domain {domain}, namespace {namespace}), it published no imu and pressure "
                    f"of {VEHICLES} within 30 s:\n{err}", pytrace=False)
    return shoal_bin


class Run:
    """A finished run beside the test agent: summary, trajectories by vehicle, the agent's log
    (one dict per tick, and what came after the last) and its report in the summary."""

    def __init__(self, out: Path, log: Path):
        #: The run's output directory.
        self.out = out
        self.summary = json.loads((out / "summary.json").read_text())
        self.rows = defaultdict(list)
        with open(out / "trajectories.csv", newline="") as f:
            for r in csv.DictReader(f):
                self.rows[r["vehicle"]].append(r)
        lines = [json.loads(line) for line in log.read_text().splitlines()]
        self.ticks = [k for k in lines if "end" not in k]
        #: Per vehicle, the frames and outcomes that came after the last tick (none if the
        #: agent died).
        self.end = next((k["end"] for k in lines if "end" in k), {})
        self.report = next(a for a in self.summary["agents"]["agents"] if a["name"] == "ros2")

    def heard(self, v, what):
        """Every `what` ("rx": frames received, "outcomes") the agent got for vehicle `v` over
        the run, in order of arrival."""
        got = [x for k in self.ticks for x in k["obs"][v][what]]
        return got + self.end.get(v, {}).get(what, [])

    def tick_at(self, t):
        """The agent's logged tick at time `t` [s]."""
        ns = round(t * 1e9)
        hits = [k for k in self.ticks if k["stamp"][0] * 10**9 + k["stamp"][1] == ns]
        assert len(hits) == 1, f"{len(hits)} ticks stamped {t} s"
        return hits[0]


def start_with_agent(shoal, tmp_path, plan, names=VEHICLES, **world_args):
    """Starts the test world and `ros2_agent.py` driving the vehicles `names` following `plan`
    (see there; unless it dies, it stops after the run's last tick, duration − TICK, and leaves
    when `finish` has seen the world end)."""
    namespace, domain = bus()
    tmp_path.mkdir(parents=True, exist_ok=True)
    path = tmp_path / "world.toml"
    path.write_text(world(namespace, domain, **world_args))
    last = round(world_args["duration"] / TICK) - 1  # ticks at 0, TICK, … before the end
    plan = {**plan, "last": last * TICK}
    out, log = tmp_path / "out", tmp_path / "agent.jsonl"
    agent_err = open(tmp_path / "agent.err", "w+")
    agent = subprocess.Popen(
        [sys.executable, str(AGENT), str(log), namespace, str(domain), ",".join(names),
         json.dumps(plan)], stdin=subprocess.PIPE, stdout=subprocess.DEVNULL, stderr=agent_err)
    sim = subprocess.Popen(
        [str(shoal), "run", str(path), "--quiet", "--no-plots", "--no-replay", "--out",
         str(out)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    return plan, last, out, log, agent, agent_err, sim


def finish(started):
    """Waits for a run `start_with_agent` started and returns the `Run`, asserting that the
    agent answered every tick once, in order: 0 … the last (or the one before it died)."""
    plan, last, out, log, agent, agent_err, sim = started
    try:
        _, sim_err = sim.communicate(timeout=600)
        agent.stdin.close()  # the world has ended: the agent may go
        agent.wait(timeout=120)
    finally:
        for p in (sim, agent):
            if p.poll() is None:
                p.kill()
                p.wait()
    agent_err.seek(0)
    said = f"world ({sim.returncode}):\n{sim_err}\nagent ({agent.returncode}):\n{agent_err.read()}"
    assert sim.returncode == 0, said
    if not log.exists() or not log.read_text():
        pytest.fail(f"the agent received no complete tick (imu and pressure of both vehicles): "
                    f"does `shoal run` publish them?\n{said}", pytrace=False)
    assert agent.returncode == (-signal.SIGKILL if "die" in plan else 0), said
    run = Run(out, log)
    if "die" in plan:
        last = round(plan["die"][0] / TICK) - 1
    stamps = [k["stamp"] for k in run.ticks]
    want = [[i * 5 // 100, i * 5 % 100 * 10**7] for i in range(last + 1)]  # i × 50 ms
    assert stamps == want, (
        f"the agent's ticks are not exactly 0 … {last * TICK:.2f} s every {TICK} s: the first "
        f"{stamps[:1]}, the last {stamps[-1:]}, {len(stamps)} in all (a tick never complete, "
        f"lost before DDS discovery matched, or returned twice?)\n{said}")
    return run


def run_with_agent(shoal, tmp_path, plan, names=VEHICLES, **world_args):
    """Runs the test world with `ros2_agent.py` driving `names` following `plan`; returns the
    `Run`."""
    return finish(start_with_agent(shoal, tmp_path, plan, names, **world_args))


def wrapped(a):
    """`a` [rad] wrapped to −π … π."""
    return math.atan2(math.sin(a), math.cos(a))


#: Setpoints of the reaching test: [depth m, heading rad] per vehicle.
SETPOINTS = [[1.2, math.pi / 2], [1.4, -2.0]]


def test_observations_are_the_run_s_and_setpoints_are_reached(ros2_shoal, tmp_path):
    """Every tick answered for both vehicles; the depth from pressure is the depth reading;
    yaw and r, while the vehicles turn to their headings, are the run's within the IMU's noise
    (roll, pitch, p and q: `test_sea_water_pressure_…`); the setpoints are reached."""
    duration = 40.0
    run = run_with_agent(ros2_shoal, tmp_path, {"setpoints": SETPOINTS}, duration=duration)
    ticks = len(run.ticks)
    assert ticks == round(duration / TICK)
    assert run.report["commands_applied"] == 2 * ticks, run.report
    assert run.report["late_replies"] == 0 and run.report["events"][1:] == [], run.report
    assert sum(run.report["rejections"].values()) == 0, run.report
    turning = 0
    for v, (depth, heading) in zip(VEHICLES, SETPOINTS):
        rows = run.rows[v]
        assert len(rows) == round(duration * 10) + 1
        for row in rows[:-1]:  # the last row, at the end: after the last tick
            t = float(row["t_s"])
            o = run.tick_at(t)["obs"][v]
            assert o["frame_id"] == f"{ros_name(v)}/base_link" and o["variance"] == 0.0
            # Pressure: 101325 Pa + ρ g × the depth reading (CSV: 7 significant digits).
            assert o["depth"] == pytest.approx(float(row["depth_reading_m"]), rel=1e-6,
                                               abs=1e-9), (v, t)
            for name, got in [("roll", o["roll"]), ("pitch", o["pitch"]), ("yaw", o["yaw"])]:
                miss = abs(wrapped(got - float(row[f"{name}_rad"])))
                assert miss < SIGMAS * ATTITUDE_NOISE, (v, t, name, miss)
            for name, got in zip(["p", "q", "r"], o["rates"]):
                miss = abs(got - float(row[f"{name}_rad_s"]))
                assert miss < SIGMAS * GYRO_NOISE, (v, t, name, miss)
            # A row where a wrong sign of r would miss by more than twice the tolerance.
            turning += abs(float(row["r_rad_s"])) > SIGMAS * GYRO_NOISE
        # Reached (40 s: the yaw loop is slow): within 5 cm and 2° at the end.
        last = rows[-1]
        assert abs(float(last["depth_reading_m"]) - depth) < 0.05, last
        assert abs(wrapped(float(last["yaw_rad"]) - heading)) < math.radians(2), last
    # The rates compared include turns (a sign error would show).
    assert turning >= 20, turning


#: Sea water [kg/m³] (`[water] density`), and by hand what the bridge's FluidPressure adds to
#: ρ g × depth: the atmosphere at the surface [Pa]; shoal's gravity [m/s²].
SEA_WATER = 1025.0
ATMOSPHERE = 101325.0
GRAVITY = 9.81
#: Sea water, and the vehicles' centre of gravity 4 mm forward and 3 mm to port of the centre
#: of buoyancy (15 mm below it, as the μAUV² preset has it): released level, they pitch nose
#: down and roll to port, swinging about −15° and −11° (and rise: buoyant in sea water).
SWINGING = f"""
[vehicles.model.body]
cog = [0.004, -0.003, 0.015]

[water]
density = {SEA_WATER}
"""


def test_sea_water_pressure_and_swinging_attitude_and_rates_are_the_run_s(ros2_shoal, tmp_path):
    """Zero thrust in sea water with an off-centre centre of gravity: at every recorded tick
    the FluidPressure is 101325 Pa + 1025 kg/m³ × 9.81 m/s² × the run's depth reading (a bridge
    using 1000 kg/m³ is off by over 49 Pa there), and roll, pitch, p and q — most of them
    further from 0 than the tolerance, and roll apart from pitch, p from q, so that a wrong
    sign or a swapped axis would miss — are the run's within the IMU's noise."""
    plan = {"actuators": [[0.0, 0.0, 0.0], [0.0, 0.0], 0], "density": SEA_WATER}
    run = run_with_agent(ros2_shoal, tmp_path, plan, duration=3.0, extra=SWINGING)
    assert run.report["commands_applied"] == 2 * len(run.ticks), run.report
    tol = {"roll": SIGMAS * ATTITUDE_NOISE, "pitch": SIGMAS * ATTITUDE_NOISE,
           "p": SIGMAS * GYRO_NOISE, "q": SIGMAS * GYRO_NOISE}
    signs = dict.fromkeys(tol, 0)  # rows where a wrong sign would miss by over twice tol
    apart = {"roll, pitch": 0, "p, q": 0}  # rows where swapping the two would miss so
    compared = 0
    for v in VEHICLES:
        for row in run.rows[v][1:-1]:  # from 0.1 s (at 0 all is level and still) to the last tick
            t = float(row["t_s"])
            o = run.tick_at(t)["obs"][v]
            depth = float(row["depth_reading_m"])
            assert depth > 0.2, row  # deep: 1000 kg/m³ would be off by 25 g × depth > 49 Pa
            # CSV: 7 significant digits of the depth, ≈ 1e-7 m ≈ 1e-3 Pa.
            assert o["pressure"] == pytest.approx(ATMOSPHERE + SEA_WATER * GRAVITY * depth,
                                                  abs=0.01), (v, t, depth)
            assert o["depth"] == pytest.approx(depth, rel=1e-6), (v, t)
            truth = {"roll": float(row["roll_rad"]), "pitch": float(row["pitch_rad"]),
                     "p": float(row["p_rad_s"]), "q": float(row["q_rad_s"])}
            got = {"roll": o["roll"], "pitch": o["pitch"], "p": o["rates"][0],
                   "q": o["rates"][1]}
            for name in tol:
                miss = abs(wrapped(got[name] - truth[name]))
                assert miss < tol[name], (v, t, name, got[name], truth[name])
                signs[name] += abs(truth[name]) > tol[name]
            apart["roll, pitch"] += abs(truth["roll"] - truth["pitch"]) > 2 * tol["roll"]
            apart["p, q"] += abs(truth["p"] - truth["q"]) > 2 * tol["p"]
            compared += 1
    assert compared == 2 * 29, compared
    # Of the 58 rows (seed 5: 52 to 58, and 36 and 54).
    assert min(signs.values()) >= 50 and min(apart.values()) >= 30, (signs, apart)


def test_raw_actuator_commands_apply_and_odometry_is_the_true_position(ros2_shoal, tmp_path):
    """`Actuators` drive the thrusters and tilts as sent (trajectories.csv's commands and tilt
    angles); with `grant_position` the `odom` position is the run's true position."""
    thrusters, tilts = [12.0, -8.0, 5.0], [0.2, -0.1]
    run = run_with_agent(ros2_shoal, tmp_path, {"actuators": [thrusters, tilts, 0],
                                                "odometry": True},
                         duration=3.0, grant_position=True)
    assert run.report["commands_applied"] == 2 * len(run.ticks), run.report
    assert sum(run.report["rejections"].values()) == 0, run.report
    compared = 0
    for v in VEHICLES:
        rows = run.rows[v]
        for row in rows[1:]:
            t = float(row["t_s"])
            assert [float(row[f"cmd_{n}_pct"]) for n in ("top", "port", "stbd")] == (
                pytest.approx(thrusters)), row
            if t <= run.ticks[-1]["t"] + 1e-9:
                got = run.tick_at(t)["obs"][v]["position"]
                want = [float(row[c]) for c in ("x_m", "y_m", "z_m")]
                assert got == pytest.approx(want, rel=1e-6, abs=1e-6), (v, t)
                compared += 1
        # The tilt drives have turned to the angles sent.
        assert [float(rows[-1][f"tilt_{n}_rad"]) for n in ("alpha", "beta")] == pytest.approx(
            tilts, abs=1e-3), rows[-1]
    assert compared == 2 * 29, compared


def test_a_nan_depth_and_an_unknown_mode_are_rejected_and_not_applied(ros2_shoal, tmp_path):
    plan = {"setpoints": SETPOINTS, "bad": [[0, 1.0, "nan_depth"], [1, 1.5, "bad_mode"]]}
    run = run_with_agent(ros2_shoal, tmp_path, plan, duration=4.0)
    rejected = run.report["rejections"]
    assert (rejected["non_finite"], rejected["invalid"]) == (1, 1), run.report
    assert run.report["commands_applied"] == 2 * len(run.ticks) - 2, run.report
    for v, (depth, heading) in zip(VEHICLES, SETPOINTS):
        for row in run.rows[v]:
            if float(row["t_s"]) >= 0.5:
                assert row["mode"] == "auto", row
                assert float(row["depth_setpoint_m"]) == pytest.approx(depth, abs=1e-6), row
                assert float(row["yaw_setpoint_rad"]) == pytest.approx(heading, abs=1e-6), row


#: The killed-agent test's world timeout [s, wall time]: once, the world waits this long for
#: the dead agent; far longer than a live agent takes to answer a tick on a loaded machine.
KILLED_TIMEOUT = 10.0


def test_a_killed_agent_leaves_its_vehicles_to_the_fallback(ros2_shoal, tmp_path):
    """The agent SIGKILLed at the tick at 2 s, after answering `answered` of the 2 vehicles (2:
    between ticks; 1: in the middle of one; the two runs side by side): the first tick not
    answered in full is `hung` (after `timeout`); from there both vehicles are under the
    fallback `surface` (depth setpoint 0) to the end, as the run's report and trajectories
    say tick by tick, and the run ends normally."""
    duration, die = 5.0, 2.0
    started = {answered: start_with_agent(ros2_shoal, tmp_path / str(answered),
                                          {"setpoints": SETPOINTS, "die": [die, answered]},
                                          duration=duration, fallback="surface",
                                          timeout=KILLED_TIMEOUT)
               for answered in (2, 1)}
    for answered, s in started.items():
        run = finish(s)  # the agent answered every tick before 2 s: 0 … 1.95 s
        s = run.summary
        assert s["simulated_s"] == pytest.approx(duration) and not s["interrupted"], s
        assert s["agents"]["stopped"] is None, s["agents"]
        hung = round(die / TICK) + (answered == 2)  # the tick [in ticks] not answered in full
        events = [(e["what"], e["step"], e["t"]) for e in run.report["events"]]
        assert events == [("attached", 0, 0.0),
                          ("hung", hung * 5, pytest.approx(hung * TICK))], (answered, events)
        # Every tick before 2 s answered, and at 2 s `answered` vehicles. Under the fallback:
        # both vehicles at every tick after the hung one (to the last, duration − TICK), and at
        # the tick at 0, before the first command (a world starts its agents' vehicles so).
        assert run.report["commands_applied"] == 2 * 40 + answered, run.report
        after = round(duration / TICK) - 1 - hung
        assert run.report["fallback_ticks"] == 2 * after + 2, (answered, run.report)
        for v, (depth, _) in zip(VEHICLES, SETPOINTS):
            for row in run.rows[v]:
                k = round(float(row["t_s"]) / TICK)  # the row's tick
                if 10 <= k < hung:
                    assert float(row["depth_setpoint_m"]) == pytest.approx(depth), row
                elif k > hung:
                    assert float(row["depth_setpoint_m"]) == 0.0, row


def test_two_lock_step_runs_give_the_same_digest(ros2_shoal, tmp_path):
    """Commands that depend on every observation (steer by the heading and depth read): two
    runs with the same seed end in the same state, bit for bit."""
    runs = [run_with_agent(ros2_shoal, tmp_path / str(i), {"follow": True}, duration=4.0)
            for i in range(2)]
    for r in runs:
        assert r.report["commands_applied"] == 2 * len(r.ticks) == 2 * 80, r.report
    assert runs[0].summary["digest"] == runs[1].summary["digest"]
    yaws = [float(r.rows["auv-0"][-1]["yaw_rad"]) for r in runs]
    assert yaws[0] == yaws[1] and abs(wrapped(yaws[0])) > 0.1, "the vehicles turned"


def test_the_ros2_school_example_aligns_the_school(ros2_shoal, tmp_path):
    """python/examples/ros2_school.py on worlds/ros2_school.toml (on a domain and namespace of
    its own, with a generous lock-step timeout): beacons over modem/tx and modem/rx turn 8
    scattered vehicles to one heading; every one of the 1200 ticks answered."""
    namespace, domain = bus()
    text = (WORLDS / "ros2_school.toml").read_text()
    for old, new in [("domain_id = 0", f"domain_id = {domain}"),
                     ('namespace = "shoal"', f'namespace = "{namespace}"'),
                     ("timeout = 2.0", f"timeout = {TIMEOUT}")]:
        assert old in text, old
        text = text.replace(old, new)
    path = tmp_path / "school.toml"
    path.write_text(text)
    out = tmp_path / "out"
    agent = subprocess.Popen([sys.executable, str(EXAMPLES / "ros2_school.py"), str(path)],
                             stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    sim = subprocess.Popen([str(ros2_shoal), "run", str(path), "--quiet", "--no-plots",
                            "--no-replay", "--out", str(out)], stdout=subprocess.DEVNULL,
                           stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.monotonic() + 600  # a safety net, not a claim
        while sim.poll() is None:
            if agent.poll() not in (None, 0):  # it gave up: the world would wait for it
                sim.kill()
                break
            assert time.monotonic() < deadline, "the run did not end within 600 s"
            time.sleep(0.1)
        sim_err = sim.communicate(timeout=60)[1]
        agent_err = agent.communicate(timeout=60)[1]
    finally:
        for p in (sim, agent):
            if p.poll() is None:
                p.kill()
                p.wait()
    assert sim.returncode == 0 and agent.returncode == 0, f"{sim_err}\n{agent_err}"
    assert "answered 1200 ticks" in agent_err, agent_err
    s = json.loads((out / "summary.json").read_text())
    report = next(a for a in s["agents"]["agents"] if a["name"] == "ros2")
    assert report["commands_applied"] == 8 * 1200 and sum(report["rejections"].values()) == 0
    rx = s["comm"]["receptions"]
    assert s["comm"]["frames_sent"] >= 8 * 59 and rx["delivered"] > 0.3 * rx["attempts"], s["comm"]
    yaws = defaultdict(list)
    with open(out / "trajectories.csv", newline="") as f:
        for r in csv.DictReader(f):
            yaws[float(r["t_s"])].append(float(r["yaw_rad"]))

    def spread(t):
        ys = yaws[t]
        assert len(ys) == 8
        mean = math.atan2(sum(map(math.sin, ys)), sum(map(math.cos, ys)))
        return max(abs(wrapped(y - mean)) for y in ys)

    assert math.degrees(spread(0.0)) > 60.0, "the school starts scattered"
    assert math.degrees(spread(60.0)) < 5.0, "and ends aligned within 5°"


# Unicast, acknowledgements, retries -------------------------------------------------------

#: The unicast world's modems (the μAUV²'s, one forward): retransmissions of an unacknowledged
#: unicast and the wait for its acknowledgement after the frame ended [s] — not the defaults
#: (3, 0.05 s), so that what is below comes from the world file.
RETRIES = 2
ACK_TIMEOUT = 0.08
#: The modem's line: bit rate [bit/s], bits per byte (8N1), link-layer header [bytes].
BIT_RATE, BITS_PER_BYTE, HEADER = 19200.0, 10, 6
#: The world's step [s] (`dt`): the link layer looks at its waits once a step.
DT = 0.01


def airtime(payload: int) -> float:
    """A frame's time on the air [s] with `payload` bytes (an acknowledgement: 0)."""
    return (payload + HEADER) * BITS_PER_BYTE / BIT_RATE


def group(name, position, heading_deg):
    """A one-vehicle group driven over ROS 2 with the unicast world's modem."""
    return f"""
[[vehicles]]
name = "{name}"
position = {list(position)}
heading_deg = {heading_deg}
agent = "ros2"

[[vehicles.model.modems]]
arq_retries = {RETRIES}
ack_timeout = {ACK_TIMEOUT}
"""


#: Four μAUV² 1 m deep (modems forward): a and b 1.5 m apart facing each other; c 0.5 m
#: beside b facing a (it hears a, 18° off a's axis); d 5 m away facing away from everyone
#: (it hears no one).
UNICAST_POSES = {"a": ((3.0, 5.0, 1.0), 0.0), "b": ((4.5, 5.0, 1.0), 180.0),
                 "c": ((4.5, 5.5, 1.0), 198.0), "d": ((8.5, 8.5, 1.0), 0.0)}
UNICAST_WORLD = "".join(group(n, p, h) for n, (p, h) in UNICAST_POSES.items())
UNICAST_VEHICLES = list(UNICAST_POSES)
#: What the agent sends: [tick s, sender index, frame].
UNICAST_FRAMES = [
    [0.1, 0, {"payload": "hello"}],  # a: a broadcast, that b and c hear
    [0.2, 0, {"payload": "for-b", "to": "b", "ack": True, "tag": 7}],
    [0.2, 2, {"payload": "bad1", "to": "nobody"}],  # c: no such vehicle
    [0.2, 2, {"payload": "bad2", "to": "c", "ack": True}],  # c: to itself
    [0.4, 1, {"payload": "to-d", "to": "d", "ack": True, "tag": 9}],  # b → d (hears nothing)
]


def ns(t):
    """`t` [s] as a stamp in ns."""
    return round(t * 1e9)


@pytest.fixture(scope="module")
def unicast_run(ros2_shoal, tmp_path_factory):
    """`UNICAST_WORLD` for 1 s beside the test agent: every vehicle holds its depth and
    heading, and sends `UNICAST_FRAMES`."""
    plan = {"setpoints": [[1.0, math.radians(h)] for _, h in UNICAST_POSES.values()],
            "frames": UNICAST_FRAMES}
    run = run_with_agent(ros2_shoal, tmp_path_factory.mktemp("unicast"), plan,
                         UNICAST_VEHICLES, duration=1.0, vehicles=UNICAST_WORLD)
    assert run.report["commands_applied"] == 4 * len(run.ticks) == 4 * 20, run.report
    return run


def payloads(frames):
    return [bytes.fromhex(f["payload"]).decode() for f in frames]


def test_an_acknowledged_unicast_reaches_its_destination_alone_and_its_sender_hears_so(
        unicast_run):
    """a → b with `ack`: b's `modem/rx` has it once, from `a`, to `b` (after a's broadcast,
    `to` empty); c, whose modem decoded it (link_pairs.csv), does not get it, nor does a get
    b's frames to d, which it decoded too; a's `modem/outcome`: acknowledged, tag 7, the
    frame's `seq`, one transmission, sent at the tick it was sent with, ended after the frame
    and b's acknowledgement were on the air and before the first wait ran out."""
    run = unicast_run
    with open(run.out / "link_pairs.csv", newline="") as f:
        decoded = {(r["sender"], r["receiver"]): int(r["delivered"]) for r in csv.DictReader(f)}
    # c: a's broadcast and unicast; a: b's acknowledgement and the three tries of b → d.
    assert (decoded[("a", "c")], decoded[("b", "a")]) == (2, 4), decoded
    rx = {v: run.heard(v, "rx") for v in UNICAST_VEHICLES}
    assert payloads(rx["b"]) == ["hello", "for-b"], rx["b"]
    hello, for_b = rx["b"]
    assert (hello["sender"], hello["to"]) == ("a", ""), hello
    assert (for_b["sender"], for_b["to"]) == ("a", "b"), for_b
    assert payloads(rx["c"]) == ["hello"], "c hears a, but the unicast is b's"
    assert rx["a"] == [] and rx["d"] == [], (rx["a"], rx["d"])
    outcomes = run.heard("a", "outcomes")
    assert len(outcomes) == 1, outcomes
    o = outcomes[0]
    assert (o["to"], o["tag"], o["acknowledged"], o["transmissions"], o["seq"]) == (
        "b", 7, True, 1, for_b["seq"]), o
    assert o["sent"] == ns(0.2), o
    earliest = 0.2 + airtime(len("for-b")) + airtime(0)
    assert ns(earliest) <= o["stamp"] < ns(0.2 + airtime(len("for-b")) + ACK_TIMEOUT), o
    assert run.summary["comm"]["link_layer"]["acks_sent"] == 1, run.summary["comm"]


def test_a_unicast_to_a_vehicle_that_hears_nothing_is_given_up_after_its_retries(unicast_run):
    """b → d with `ack`, d hearing no one: b's `modem/outcome` says not acknowledged after
    1 + RETRIES transmissions. By hand: each try of the 4-byte frame is on the air for
    (4 + 6) × 10 / 19200 s = 5.21 ms, the wait runs ACK_TIMEOUT = 80 ms after it, and the
    link layer retransmits (or gives up) at the first step (DT = 10 ms) at or after its end:
    ceil(85.2 ms / DT) × DT = 90 ms a try, tries at 0.40, 0.49, 0.58 s, given up at 0.67 s."""
    run = unicast_run
    outcomes = run.heard("b", "outcomes")
    assert len(outcomes) == 1, outcomes
    o = outcomes[0]
    assert (o["to"], o["tag"], o["acknowledged"], o["transmissions"]) == (
        "d", 9, False, 1 + RETRIES), o
    assert o["sent"] == ns(0.4), o
    per_try = math.ceil((airtime(len("to-d")) + ACK_TIMEOUT) / DT) * DT
    assert per_try == pytest.approx(0.09)
    assert o["stamp"] == pytest.approx(ns(0.4 + (1 + RETRIES) * per_try), abs=1000), o
    assert run.heard("d", "rx") == [] and run.heard("d", "outcomes") == []
    link = run.summary["comm"]["link_layer"]
    assert (link["acknowledged"], link["gave_up"], link["retransmissions"]) == (
        1, 1, RETRIES), link


def test_frames_to_no_vehicle_or_to_the_sender_itself_are_bad_frames(unicast_run):
    """c's frames to `nobody` (no vehicle's name) and to `c` itself are counted as bad frames,
    nothing else is rejected, and neither went on the air: the run sent 3 frames (hello,
    for-b, to-d), c has no outcome, and no one received them."""
    run = unicast_run
    rejected = run.report["rejections"]
    assert rejected["bad_frames"] == 2, rejected
    assert sum(rejected.values()) == 2, rejected
    assert run.summary["comm"]["frames_sent"] == 3, run.summary["comm"]
    assert run.heard("c", "outcomes") == []
    every = [p for v in UNICAST_VEHICLES for p in payloads(run.heard(v, "rx"))]
    assert "bad1" not in every and "bad2" not in every, every
