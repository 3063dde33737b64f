"""`shoal.agent` (the shared-memory agent API, formerly `shoal_agent`) still drives a world
run by `shoal run` in another process: the goto example takes a vehicle to its depth and
heading, the README's hello agent (jittered beacons) gets its frames delivered, and an agent
sends unicasts with and without acknowledgement and learns what became of them."""

import csv
import json
import math
import os
import struct
import subprocess
import sys
from pathlib import Path

import pytest

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


# Addressed frames: worlds/agents_unicast.toml (a faces b 1.2 m ahead; c beside b hears a; d
# 8 m away, facing away, hears nothing), driven by an agent running in this process.

#: Physics step of the world [s]: the link layer looks at its timers, and acknowledgements
#: leave, at the start of a step.
DT = 0.01
#: The agent's delay after the tick [s] (off the step grid on purpose).
DELAY = 0.013
#: Airtime of the agent's 8-byte frames: (8 + 6 header bytes) x 10 bits at 19,200 bit/s [s].
AIRTIME = 14 * 10 / 19200
#: Airtime of an acknowledgement (the 6-byte header alone) [s].
ACK_AIRTIME = 6 * 10 / 19200
#: The world's modems' ack_timeout [s] and arq_retries.
ACK_TIMEOUT = 0.05
ARQ_RETRIES = 2


def next_step(t):
    """The first step boundary at or after `t` [s]."""
    return math.ceil(t / DT - 1e-9) * DT


class Scripted(shoal.agent.Agent):
    """Sends the frames of `plan` — (at [s], from, to or None, ack, tag), each on its sender's
    first tick at or after `at`, DELAY after it, payload the tag and the sender (u32 LE) — and
    records what its vehicles received and learnt of their acknowledged frames."""

    def __init__(self, plan):
        self.plan = list(plan)
        self.rx = []  # (vehicle, ReceivedFrame)
        self.outcomes = []  # (vehicle, FrameOutcome)

    def tick(self, obs, cmd):
        self.rx += [(obs.vehicle, f) for f in shoal.agent.received_frames(obs)]
        self.outcomes += [(obs.vehicle, o) for o in shoal.agent.outcomes(obs)]
        due = [p for p in self.plan if p[1] == obs.vehicle and obs.time + 1e-9 >= p[0]]
        for p in due:
            self.plan.remove(p)
            _, sender, to, ack, tag = p
            payload = struct.pack("<II", tag, sender)
            assert shoal.agent.send(cmd, shoal.agent.ALL_MODEMS, payload, DELAY,
                                    to=to, ack=ack, tag=tag)

    def tags_at(self, vehicle):
        """The tags of the frames `vehicle` received, in order."""
        return [struct.unpack_from("<I", f.payload)[0] for v, f in self.rx if v == vehicle]


def run_in_process(shoal_bin, tmp_path, agent):
    """Runs worlds/agents_unicast.toml (3 s) with `agent` attached from this process as
    `link`; returns the summary."""
    prefix = f"pytest-{os.getpid()}-{tmp_path.name}"[:60]
    out = tmp_path / "out"
    sim = subprocess.Popen(
        [str(shoal_bin), "run", str(WORLDS / "agents_unicast.toml"), "--quiet", "--no-plots",
         "--no-replay", "--prefix", prefix, "--out", str(out)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        ended = shoal.agent.run(prefix, "link", agent, wait=60.0)
        _, sim_err = sim.communicate(timeout=120)
    finally:
        sim.kill()
    assert ended is shoal.agent.Ended.WORLD_ENDED
    assert sim.returncode == 0, sim_err
    return json.loads((out / "summary.json").read_text())


def test_an_acknowledged_unicast_reaches_its_destination_alone_and_comes_back_tagged(
        shoal_bin, tmp_path):
    agent = Scripted([(0.5, 0, 1, True, 7), (1.0, 0, 1, False, 8), (1.5, 0, None, False, 9)])
    summary = run_in_process(shoal_bin, tmp_path, agent)
    # Only the acknowledged frame ends with an outcome, at vehicle 0, with its tag, after one
    # transmission: on the air when handed over, decoded by b in that step, b's
    # acknowledgement at the next step boundary, decoded ACK_AIRTIME later.
    assert len(agent.outcomes) == 1, agent.outcomes
    vehicle, o = agent.outcomes[0]
    assert (vehicle, o.to, o.tag, o.acknowledged, o.transmissions) == (0, 1, 7, True, 1), o
    sent = 0.5 + DELAY
    assert o.sent == pytest.approx(sent, abs=1e-9)
    assert o.t == pytest.approx(next_step(sent + AIRTIME) + ACK_AIRTIME, abs=1e-9), o
    # b: both unicasts flagged as addressed to it, the broadcast not; all from vehicle 0; the
    # acknowledged one with the sequence number its outcome names.
    at_b = [f for v, f in agent.rx if v == 1]
    assert agent.tags_at(1) == [7, 8, 9]
    assert [f.unicast for f in at_b] == [True, True, False]
    assert all(f.sender == 0 and f.power > 0 for f in at_b)
    assert at_b[0].seq == o.seq
    assert at_b[0].t == pytest.approx(sent + AIRTIME, abs=1e-9)
    # c hears a (the broadcast) but is handed neither unicast; d hears nothing.
    assert agent.tags_at(2) == [9]
    assert agent.tags_at(3) == []
    link = summary["comm"]["link_layer"]
    assert (link["acknowledged"], link["gave_up"], link["acks_sent"]) == (1, 0, 1), link
    assert sum(summary["agents"]["agents"][0]["rejections"].values()) == 0


def test_an_acknowledged_unicast_out_of_reach_is_given_up_after_its_retries(
        shoal_bin, tmp_path):
    agent = Scripted([(1.0, 0, 3, True, 8)])
    summary = run_in_process(shoal_bin, tmp_path, agent)
    assert len(agent.outcomes) == 1, agent.outcomes
    vehicle, o = agent.outcomes[0]
    assert (vehicle, o.to, o.tag, o.acknowledged) == (0, 3, 8, False), o
    assert o.transmissions == 1 + ARQ_RETRIES
    # By hand: each wait ends ACK_TIMEOUT after its copy ended and is noticed at the next step
    # boundary, where the retransmission starts; the last wait's end is the outcome.
    sent = 1.0 + DELAY
    assert o.sent == pytest.approx(sent, abs=1e-9)
    start = sent
    for _ in range(ARQ_RETRIES):
        start = next_step(start + AIRTIME + ACK_TIMEOUT)
    last_end = start + AIRTIME
    assert o.t == pytest.approx(next_step(last_end + ACK_TIMEOUT), abs=1e-9), o
    assert last_end + ACK_TIMEOUT <= o.t < last_end + ACK_TIMEOUT + DT
    assert agent.tags_at(3) == []
    link = summary["comm"]["link_layer"]
    assert (link["acknowledged"], link["gave_up"], link["retransmissions"]) == (0, 1, 2), link


def test_send_writes_the_destination_the_flag_and_the_tag():
    from shoal.agent import BROADCAST, Command, frame_flags, send

    cmd = Command()
    assert send(cmd, 0, b"all")
    assert send(cmd, 1, b"one", 0.02, to=5, ack=True, tag=99)
    broadcast, unicast = cmd.frames[0], cmd.frames[1]
    assert (broadcast.peer, broadcast.flags, broadcast.tag) == (BROADCAST, 0, 0)
    assert (unicast.peer, unicast.flags, unicast.tag, unicast.modem) == (5, frame_flags.ACK, 99, 1)
    assert bytes(unicast.data[:unicast.len]) == b"one"
    with pytest.raises(ValueError, match="needs a destination"):
        send(cmd, 0, b"x", ack=True)
    with pytest.raises(ValueError):
        send(cmd, 0, b"x", to=BROADCAST)
    with pytest.raises(ValueError):
        send(cmd, 0, b"x", to=1, tag=-1)
    assert cmd.n_frames == 2
