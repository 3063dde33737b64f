"""`shoal.agent` (the shared-memory agent API, formerly `shoal_agent`) still drives a world
run by `shoal run` in another process: the goto example takes a vehicle to its depth and
heading, and the README's hello agent (jittered beacons) gets its frames delivered."""

import csv
import os
import subprocess
import sys
from pathlib import Path

import shoal.agent
from conftest import REPO, WORLDS

EXAMPLES = REPO / "python" / "examples"


def run_with_agent(shoal_bin, tmp_path, world, seconds, agent_args):
    """Runs `world` for `seconds` with the agent command `agent_args` (given the prefix
    first); returns the summary, the trajectories' rows and the agent's stderr."""
    prefix = f"pytest-{os.getpid()}-{tmp_path.name}"[:60]
    out = tmp_path / "out"
    sim = subprocess.Popen(
        [str(shoal_bin), "run", str(world), "--quiet", "--no-plots", "--no-replay",
         "--duration", str(seconds), "--prefix", prefix, "--out", str(out)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        agent = subprocess.run([sys.executable, *map(str, agent_args[:1]), prefix,
                                *map(str, agent_args[1:])],
                               capture_output=True, text=True, timeout=120)
        sim_out, sim_err = sim.communicate(timeout=120)
    finally:
        sim.kill()
    assert agent.returncode == 0, f"agent: {agent.stderr}\nworld: {sim.stderr}"
    assert sim.returncode == 0, sim_err
    import json
    summary = json.loads((out / "summary.json").read_text())
    with open(out / "trajectories.csv") as f:
        rows = list(csv.DictReader(f))
    return summary, rows, agent.stderr


def test_the_goto_agent_drives_a_vehicle_over_shared_memory(shoal_bin, tmp_path):
    summary, rows, log = run_with_agent(
        shoal_bin, tmp_path, WORLDS / "agents_goto.toml", 40.0,
        [EXAMPLES / "goto.py", "pilot", "1.5", "90"])
    agent = summary["agents"]["agents"][0]
    assert agent["events"][0]["what"] == "attached", agent["events"]
    assert agent["commands_applied"] >= 40.0 / 0.05 - 2
    assert sum(agent["rejections"].values()) == 0
    last = rows[-1]
    assert abs(float(last["depth_reading_m"]) - 1.5) < 0.05, last
    assert abs(float(last["yaw_rad"]) - 1.5708) < 0.02, last


def test_the_readme_hello_agent_is_heard(shoal_bin, tmp_path):
    summary, _, log = run_with_agent(
        shoal_bin, tmp_path, WORLDS / "agents_school.toml", 10.0,
        [EXAMPLES / "hello.py", "school"])
    comm = summary["comm"]
    # 8 vehicles, one "hello" a second each, heard by most of the 7 others.
    assert 70 <= comm["frames_sent"] <= 90, comm
    rx = comm["receptions"]
    assert rx["delivered"] > 0.6 * rx["attempts"], rx
    assert f"heard {rx['delivered']} frames" in log


def test_the_readme_snippet_is_the_hello_example():
    readme = (REPO / "python" / "README.md").read_text()
    start = readme.index("class Hello(Agent):")
    block = readme[start:readme.index("\n\nrun(", start)].strip()
    assert block in (EXAMPLES / "hello.py").read_text()


def test_shoal_agent_is_an_alias_of_shoal_agent():
    import shoal_agent
    import shoal_agent.protocol

    assert shoal_agent.Agent is shoal.agent.Agent
    assert shoal_agent.protocol is shoal.agent.protocol
    assert shoal_agent.protocol.FRAME_BYTES == 64
