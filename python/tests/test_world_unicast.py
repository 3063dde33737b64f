"""`shoal.World.send` with a destination and acknowledgement: a unicast reaches its
destination alone, is acknowledged, and `outcomes` says so with the sender's tag and the
latency the airtimes give; a destination out of range makes the sender retransmit
`arq_retries` times, `ack_timeout` apart, and give up; bad destinations are refused."""

import numpy as np
import pytest

import shoal

#: Airtime of a frame with `n` payload bytes on the μAUV² modem [s]: (n + 6 header bytes)
#: × 10 line bits per byte (8N1) at 19.2 kbit/s.
def airtime(n):
    return (n + 6) * 10 / 19_200.0


ACK = airtime(0)  # an acknowledgement is a header-only frame
DT = 0.01
TIMEOUT = 0.05
RETRIES = 2

#: `a` faces `b` 1.25 m away; `c` faces `a` too, 0.3 m beside `b` (it hears `a`); `d` faces
#: `a` 7 m away, beyond the modems' reach. One front modem each, two retries, 50 ms timeout.
WORLD = f"""
seed = 8
dt = {DT}
[pool]
size = [14.0, 6.0, 3.0]
""" + "".join(
    f"""
[[vehicles]]
name = "{name}"
position = [{x}, {y}, 1.5]
heading_deg = {heading}
[[vehicles.model.modems]]
arq_retries = {RETRIES}
ack_timeout = {TIMEOUT}
"""
    for name, x, y, heading in [("a", 4.0, 3.0, 0), ("b", 5.25, 3.0, 180),
                                ("c", 5.25, 3.3, 180), ("d", 11.0, 3.0, 180)]
)


def run_until_outcome(w, steps=200):
    """Steps until an outcome comes; returns it and every frame received meanwhile."""
    got = []
    for _ in range(steps):
        w.step(steps=1)
        rx = w.received
        got += [(int(v), int(s), bool(u), bytes(p[:n])) for v, s, u, p, n in
                zip(rx["vehicle"], rx["sender"], rx["unicast"], rx["payload"], rx["length"])]
        out = w.outcomes
        if len(out["tag"]):
            return {k: v.tolist() for k, v in out.items()}, got
    raise AssertionError(f"no outcome in {steps} steps")


def test_an_acknowledged_unicast_reaches_its_destination_alone_and_comes_back_with_its_tag():
    w = shoal.World(WORLD, threads=1)
    # A broadcast first: `c` is within `a`'s reach, so what keeps the unicast from it is the
    # address, not the optics.
    w.send(0, b"all", delay=0.0)
    w.step(steps=5)
    rx = w.received
    assert sorted(rx["vehicle"].tolist()) == [1, 2] and not rx["unicast"].any()
    w.send(0, b"hello", to=1, ack=True, tag=42)
    out, got = run_until_outcome(w)
    assert got == [(1, 0, True, b"hello")], "the destination alone takes it, once"
    assert out["vehicle"] == [0] and out["to"] == [1] and out["tag"] == [42]
    assert out["acknowledged"] == [True] and out["transmissions"] == [1]
    # Handed over at a step boundary, on the air at once for 5.7 ms; the acknowledgement
    # leaves at the first step boundary after the frame ended (≤ one step later) and takes
    # 3.1 ms: the latency is the two airtimes plus at most a step.
    latency = out["t"][0] - out["sent"][0]
    assert airtime(5) + ACK - 1e-9 <= latency <= airtime(5) + ACK + DT + 1e-9, latency
    # Nothing else ends: no retransmission, no second outcome.
    w.step(steps=30)
    assert len(w.outcomes["tag"]) == 0
    # Two frames of `a`; `b`'s acknowledgement is counted apart (summary.json `acks_sent`).
    np.testing.assert_array_equal(w.frames_sent, [2, 0, 0, 0])


def test_a_unicast_nobody_can_hear_is_retransmitted_until_its_retries_are_used_up():
    w = shoal.World(WORLD, threads=1)
    t0 = w.time
    w.send(0, b"far", to=3, ack=True, tag=7)
    out, got = run_until_outcome(w)
    assert got == [] and out["to"] == [3] and out["tag"] == [7]
    assert out["acknowledged"] == [False] and out["transmissions"] == [1 + RETRIES]
    # Each try: the frame's airtime, then the wait; a retransmission leaves at the first
    # step boundary after the wait ran out (≤ one step later), and the sender gives up at the
    # first step boundary after the last wait ran out.
    tries = 1 + RETRIES
    least = tries * (airtime(3) + TIMEOUT)
    assert out["sent"] == [t0]
    assert least - 1e-9 <= out["t"][0] - t0 <= least + tries * DT + 1e-9, out["t"][0] - t0
    np.testing.assert_array_equal(w.frames_sent, [1, 0, 0, 0])  # retransmissions apart


def test_bad_destinations_are_refused_naming_the_frame():
    w = shoal.World(WORLD, threads=1)
    for kwargs, words in [(dict(to=0), "itself"), (dict(to=9), "does not exist"),
                          (dict(ack=True), "needs a destination"), (dict(to=-2), "vehicle id"),
                          (dict(to=1, tag=-1), "tag")]:
        with pytest.raises(shoal.CommandError, match=words):
            w.send(0, b"x", **kwargs)
    # Columns: one value per frame.
    w.send([0, 1], [b"p", b"q"], delay=[0.0, 0.02], to=[1, 0], ack=[True, False], tag=[1, 2])
    with pytest.raises(shoal.CommandError, match="one value per frame"):
        w.send([0, 1], b"x", to=[1, 0, 2])
    w.step(steps=5)
    # The two frames of the call that passed went on the air; the refused calls left nothing.
    np.testing.assert_array_equal(w.frames_sent, [1, 1, 0, 0])
