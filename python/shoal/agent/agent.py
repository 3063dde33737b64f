"""The agent side in Python: attach to a running shoal world as agent `name`, receive each
control tick's observations of its vehicles, answer with one command per vehicle. Mirrors
`crates/shoal-bridge/src/agent.rs`::

    from shoal.agent import Agent, mode, run, set_mode

    class Dive(Agent):
        '''Every vehicle dives to 1.5 m and turns north-east.'''

        def tick(self, obs, cmd):
            set_mode(cmd, mode.AUTO, 1.5, 0.785)

    run("my-world", "divers", Dive(), wait=30.0)

Services: the world creates `shoal/<prefix>/<agent>/obs` (it publishes `[Observation]`
slices, one element per vehicle of the agent whose control tick it is) and
`shoal/<prefix>/<agent>/cmd` (the agent publishes `[Command]` slices, one element per
observed vehicle, carrying the observation's `step`). The last observation slice of a run has
`flags.END` set: the agent then leaves without answering. An agent that leaves earlier (Ctrl-C,
`close`) sends a one-element `kind.LEAVE` slice first and waits briefly for the world's END
acknowledgement.

Frames: `send(cmd, modem, payload)` broadcasts; with `to=VEHICLE` the frame is for that vehicle
alone (a unicast), and with `ack=True` also acknowledged and retransmitted until it is; what
became of it comes back in a later observation, with the `tag` you gave it::

    def tick(self, obs, cmd):
        for f in received_frames(obs):          # ReceivedFrame: payload, sender, unicast, ...
            ...
        for o in outcomes(obs):                 # FrameOutcome: tag, acknowledged, ...
            if not o.acknowledged:
                print(f"vehicle {o.to} never confirmed frame {o.tag}")
        send(cmd, ALL_MODEMS, b"hi", to=3, ack=True, tag=42)
"""

import ctypes
import enum
import time
from typing import Iterator, NamedTuple, Optional, Sequence, Tuple

import iceoryx2 as iox2

from .protocol import (
    ALL_MODEMS,
    BROADCAST,
    FRAME_BYTES,
    MAX_OUTCOMES,
    MAX_RX_FRAMES,
    MAX_TX_FRAMES,
    PROTOCOL_VERSION,
    Command,
    Observation,
    flags,
    frame_flags,
    kind,
)

__all__ = [
    "Agent",
    "AgentLink",
    "AgentTaken",
    "BridgeError",
    "Ended",
    "FrameOutcome",
    "NoWorld",
    "ReceivedFrame",
    "keep",
    "main",
    "outcomes",
    "received",
    "received_frames",
    "run",
    "send",
    "service_name",
    "set_mode",
]

_OBS_SIZE = ctypes.sizeof(Observation)
_CMD_SIZE = ctypes.sizeof(Command)

# Waiting for the next observation: poll without pause this long [s], then nap briefly, and
# after a longer silence nap longer (a lock-step world answers within a few hundred µs).
_SPIN_S = 0.001
_SHORT_NAP_S = 0.0001
_LONG_NAP_AFTER_S = 0.1
_LONG_NAP_S = 0.001
# Longest wait for the world to acknowledge a LEAVE [s].
_LEAVE_ACK_S = 0.5


class BridgeError(Exception):
    """A problem of the bridge (setting up services, talking to the world)."""


class NoWorld(BridgeError):
    """No world with this prefix and agent name appeared in time."""


class AgentTaken(BridgeError):
    """Another process is already attached as this agent."""


class Ended(enum.Enum):
    """What ended `AgentLink.run`."""

    #: The world said the run is over.
    WORLD_ENDED = "world ended"
    #: No observation arrived for the idle timeout (the world died or stalled).
    SILENT = "silent"


class Agent:
    """A swarm behaviour run by `AgentLink.run`: `tick` is called once per vehicle and tick."""

    def tick(self, obs: Observation, cmd: Command) -> None:
        """Fill `cmd` (pre-set to "keep", for `obs.vehicle` and `obs.step`) from `obs`.

        Both are valid only during the call: copy what you want to keep.
        """
        raise NotImplementedError("an Agent overrides tick(self, obs, cmd)")


def service_name(prefix: str, agent: str, leaf: str) -> str:
    """Name of an agent's service `leaf` (`obs` or `cmd`) in the world with `prefix`."""
    return f"shoal/{prefix}/{agent}/{leaf}"


def _fill_keep(cmd: Command, obs: Observation) -> None:
    cmd.version = PROTOCOL_VERSION
    cmd.vehicle = obs.vehicle
    cmd.step = obs.step
    cmd.kind = kind.KEEP


def keep(obs: Observation) -> Command:
    """A "keep the setpoints" command for the vehicle and step of `obs`."""
    cmd = Command()
    _fill_keep(cmd, obs)
    return cmd


def set_mode(
    cmd: Command, mode: int, depth: float, yaw: float, surge: float = 0.0, sway: float = 0.0
) -> None:
    """Sets controller mode `mode` (one of `protocol.mode`) with its setpoints: depth [m,
    positive down], heading [rad], surge and sway forces [N]."""
    cmd.kind = kind.MODE
    cmd.mode = mode
    cmd.depth = depth
    cmd.yaw = yaw
    cmd.surge = surge
    cmd.sway = sway


_U32 = 0xFFFFFFFF


def send(
    cmd: Command,
    modem: int,
    payload: bytes,
    delay: float = 0.0,
    *,
    to: Optional[int] = None,
    ack: bool = False,
    tag: int = 0,
) -> bool:
    """Adds a frame for modem `modem` (`ALL_MODEMS` for all in sync), `delay` [s] after the
    tick: a broadcast, or with `to` a unicast for that vehicle id alone. With `ack` (needs
    `to`) the destination acknowledges it and the world retransmits it until it does (at most
    the modem's `arq_retries` times); what became of it comes back as a `FrameOutcome`
    carrying `tag` (0 … 2**32 - 1, of your choosing) in a later observation (`outcomes`).

    Returns False (and adds nothing) when the payload exceeds `FRAME_BYTES` or the command
    already holds `MAX_TX_FRAMES` frames. Raises ValueError for a modem, destination or tag
    out of range, or `ack` without `to`. The world checks the rest — `to` must be another
    vehicle of the world — and counts a frame it refuses in the agent's `bad_frames`."""
    if not 0 <= modem <= ALL_MODEMS:
        raise ValueError(f"modem {modem}: a modem index 0…254 or ALL_MODEMS (255)")
    if to is not None and not 0 <= to < BROADCAST:
        raise ValueError(f"to = {to}: a vehicle id 0 … {BROADCAST - 1}, or None to broadcast")
    if ack and to is None:
        raise ValueError("ack=True needs a destination `to`: a broadcast is never acknowledged")
    if not 0 <= tag <= _U32:
        raise ValueError(f"tag {tag}: 0 … {_U32}")
    data = bytes(payload)
    n = cmd.n_frames
    if n >= MAX_TX_FRAMES or len(data) > FRAME_BYTES:
        return False
    f = cmd.frames[n]  # a view into cmd
    f.t = delay
    f.modem = modem
    f.flags = frame_flags.ACK if ack else 0
    f.peer = BROADCAST if to is None else to
    f.tag = tag
    f.seq = 0
    f.len = len(data)
    ctypes.memmove(ctypes.addressof(f.data), data, len(data))
    cmd.n_frames = n + 1
    return True


class ReceivedFrame(NamedTuple):
    """A frame one of your vehicles received (see `received_frames`)."""

    #: The payload.
    payload: bytes
    #: Which of the vehicle's modems received it.
    modem: int
    #: Optical power at that modem [W].
    power: float
    #: End of the reception [s].
    t: float
    #: The sending vehicle's id.
    sender: int
    #: The sender's sequence number of the frame (`FrameOutcome.seq` at the sender).
    seq: int
    #: Whether it was addressed to this vehicle alone (a unicast), not broadcast.
    unicast: bool


class FrameOutcome(NamedTuple):
    """What became of a frame sent with `ack=True` (see `outcomes`)."""

    #: When it ended: the acknowledgement decoded, or the wait after its last transmission
    #: ran out [s].
    t: float
    #: When it was handed over (the tick plus its delay) [s].
    sent: float
    #: Its destination vehicle id.
    to: int
    #: The tag you gave it.
    tag: int
    #: The sender's sequence number of the frame (`ReceivedFrame.seq` at the destination).
    seq: int
    #: Times it went on the air: 1 + retransmissions (0: refused by a full transmit queue).
    transmissions: int
    #: True: the destination acknowledged it; False: given up after the retries.
    acknowledged: bool


def received_frames(obs: Observation) -> Iterator[ReceivedFrame]:
    """The frames received since the last tick, in order of arrival (`obs.frames_dropped`
    counts those beyond `MAX_RX_FRAMES`)."""
    for i in range(min(obs.n_frames, MAX_RX_FRAMES)):
        f = obs.frames[i]
        yield ReceivedFrame(
            payload=bytes(f.data)[: min(f.len, FRAME_BYTES)],
            modem=f.modem,
            power=f.power,
            t=f.t,
            sender=f.peer,
            seq=f.seq,
            unicast=bool(f.flags & frame_flags.UNICAST),
        )


def received(obs: Observation) -> Iterator[Tuple[bytes, int, float, float]]:
    """The frames received since the last tick, in order of arrival, as
    `(payload, modem, power [W], t [s, end of reception])` (`received_frames` says more)."""
    for f in received_frames(obs):
        yield f[:4]


def outcomes(obs: Observation) -> Iterator[FrameOutcome]:
    """What became of the vehicle's frames sent with `ack=True` since the last tick, in
    order (`obs.outcomes_dropped` counts those beyond `MAX_OUTCOMES`)."""
    for i in range(min(obs.n_outcomes, MAX_OUTCOMES)):
        o = obs.outcomes[i]
        yield FrameOutcome(
            t=o.t,
            sent=o.sent,
            to=o.to,
            tag=o.tag,
            seq=o.seq,
            transmissions=o.transmissions,
            acknowledged=bool(o.acknowledged),
        )


class AgentLink:
    """An attached agent (see `attach`). Use it as a context manager, or call `close`."""

    def __init__(self, node, obs_svc, cmd_svc, obs_sub, cmd_pub) -> None:
        self._node = node
        self._obs_svc = obs_svc
        self._cmd_svc = cmd_svc
        self._obs_sub = obs_sub
        self._cmd_pub = cmd_pub
        #: Longest wait for the next observation before `Ended.SILENT` [s].
        self.idle_timeout = 10.0
        #: Ticks answered.
        self.ticks = 0
        #: The world ended the run (no goodbye needed).
        self._ended = False

    @classmethod
    def attach(cls, prefix: str, agent: str, wait: float = 60.0) -> "AgentLink":
        """Attaches as `agent` to the world with `prefix`, waiting up to `wait` seconds for
        the world to appear. Raises `NoWorld` or `AgentTaken`."""
        config = iox2.config.default()
        node = (
            iox2.NodeBuilder.new()
            .name(iox2.NodeName.new(f"shoal-agent.{agent}"))
            .config(config)
            # Signals stay with Python (Ctrl-C raises KeyboardInterrupt); this link never
            # calls Node.wait, the only user of iceoryx2's own termination handling.
            .signal_handling_mode(iox2.SignalHandlingMode.Disabled)
            .create(iox2.ServiceType.Ipc)
        )
        obs_svc = cmd_svc = obs_sub = cmd_pub = None
        try:
            obs_name = iox2.ServiceName.new(service_name(prefix, agent, "obs"))
            cmd_name = iox2.ServiceName.new(service_name(prefix, agent, "cmd"))
            start = time.monotonic()
            while True:
                try:
                    obs_svc = (
                        node.service_builder(obs_name)
                        .publish_subscribe(iox2.Slice[Observation])
                        .open()
                    )
                    cmd_svc = (
                        node.service_builder(cmd_name)
                        .publish_subscribe(iox2.Slice[Command])
                        .open()
                    )
                    break
                except iox2.PublishSubscribeOpenError as e:
                    obs_svc = cmd_svc = None
                    if time.monotonic() - start >= wait:
                        raise NoWorld(
                            f"no world with prefix `{prefix}` and agent `{agent}` appeared "
                            f"within {wait} s (last: {e!r})"
                        ) from None
                    time.sleep(0.02)
            try:
                cmd_pub = (
                    cmd_svc.publisher_builder()
                    .initial_max_slice_len(64)
                    .allocation_strategy(iox2.AllocationStrategy.PowerOfTwo)
                    .create()
                )
                obs_sub = obs_svc.subscriber_builder().buffer_size(2).create()
            except (iox2.PublisherCreateError, iox2.SubscriberCreateError):
                raise AgentTaken(
                    f"agent `{agent}` is already attached to this world "
                    "(one process per agent name)"
                ) from None
        except BaseException:
            for port in (obs_sub, cmd_pub):
                if port is not None:
                    port.delete()
            raise
        return cls(node, obs_svc, cmd_svc, obs_sub, cmd_pub)

    def __enter__(self) -> "AgentLink":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        """Detaches: unless the world ended the run, says LEAVE and waits (at most 0.5 s)
        for the world's acknowledgement, so the world records `left` rather than `gone`;
        then releases the ports, the services and the node (idempotent). The node has no
        explicit delete in Python: it goes with its last reference, held only here."""
        if self._obs_sub is not None and not self._ended:
            try:
                bye = Command()
                bye.version = PROTOCOL_VERSION
                bye.vehicle = 0xFFFFFFFF
                bye.kind = kind.LEAVE
                self.send([bye])
                deadline = time.perf_counter() + _LEAVE_ACK_S
                while not self._ended:
                    left = deadline - time.perf_counter()
                    if left <= 0 or self.receive(left) is None:
                        break
            except Exception:
                pass  # the world is gone: nothing to say goodbye to
        for attr in ("_obs_sub", "_cmd_pub"):
            port = getattr(self, attr, None)
            if port is not None:
                setattr(self, attr, None)
                port.delete()
        self._obs_svc = None
        self._cmd_svc = None
        self._node = None

    def __del__(self) -> None:
        try:
            self.close()
        except Exception:
            pass

    def _live(self):
        if self._obs_sub is None:
            raise BridgeError("the link is closed")
        return self._obs_sub

    def receive(self, timeout: float) -> Optional[ctypes.Array]:
        """The next observation slice as a (copied) ctypes array of `Observation`, the newest
        if several are queued; busy-polls briefly, then naps; `None` after `timeout` seconds.
        The slice of the world's last tick has `flags.END` set."""
        sub = self._live()
        start = time.perf_counter()
        while True:
            newest = None
            while True:
                sample = sub.receive()
                if sample is None:
                    break
                try:
                    n = sample.header.number_of_elements  # elements (Slice.len() is bytes)
                    newest = (Observation * n)()
                    ctypes.memmove(newest, sample.payload_ptr, n * _OBS_SIZE)
                finally:
                    sample.delete()
            if newest is not None:
                if any(o.flags & flags.END for o in newest):
                    self._ended = True
                return newest
            waited = time.perf_counter() - start
            if waited >= timeout:
                return None
            if waited < _SPIN_S:
                continue
            time.sleep(_SHORT_NAP_S if waited < _LONG_NAP_AFTER_S else _LONG_NAP_S)

    def send(self, cmds: Sequence[Command]) -> None:
        """Sends one reply slice: the commands (all for the same step), a ctypes array of
        `Command` or any sequence of them. Nothing is sent for an empty one."""
        self._live()
        n = len(cmds)
        if n == 0:
            return
        reply = self._cmd_pub.loan_slice_uninit(n)
        try:
            if isinstance(cmds, ctypes.Array) and cmds._type_ is Command:
                ctypes.memmove(reply.payload_ptr, cmds, n * _CMD_SIZE)
            else:
                base = reply.payload_ptr
                for i, c in enumerate(cmds):
                    if not isinstance(c, Command):
                        raise TypeError(f"cmds[{i}] is a {type(c).__name__}, not a Command")
                    ctypes.memmove(base + i * _CMD_SIZE, ctypes.addressof(c), _CMD_SIZE)
        except BaseException:
            reply.delete()
            raise
        reply.assume_init().send()

    def run(self, agent: Agent) -> Ended:
        """Runs `agent` until the world ends the run or falls silent."""
        while True:
            obs = self.receive(self.idle_timeout)
            if obs is None:
                self._node.try_cleanup_dead_nodes()
                return Ended.SILENT
            if any(o.flags & flags.END for o in obs):
                return Ended.WORLD_ENDED
            cmds = (Command * len(obs))()
            for o, c in zip(obs, cmds):
                _fill_keep(c, o)
                agent.tick(o, c)
            self.send(cmds)
            self.ticks += 1


def run(
    prefix: str, name: str, agent: Agent, wait: float = 60.0, idle_timeout: float = 10.0
) -> Ended:
    """Attaches as `name` to the world with `prefix` (waiting up to `wait` s for it), runs
    `agent` until the world ends the run (or no observation comes for `idle_timeout` s) and
    detaches, also on exceptions and KeyboardInterrupt."""
    with AgentLink.attach(prefix, name, wait) as link:
        link.idle_timeout = idle_timeout
        return link.run(agent)


def main(label: str, prefix: str, name: str, agent: Agent, wait: float = 60.0) -> int:
    """`run` for a command-line agent: reports on stderr as `label` and returns the exit
    status — 0 when the world ended the run, 1 when it fell silent or could not be reached,
    130 on Ctrl-C, 143 on SIGTERM (both detach with a goodbye first)."""
    import signal
    import sys

    # `kill` (SIGTERM) detaches cleanly too, like Ctrl-C.
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))
    try:
        with AgentLink.attach(prefix, name, wait) as link:
            print(f"{label}: attached to `{prefix}` as `{name}`", file=sys.stderr)
            ended = link.run(agent)
            if ended is Ended.WORLD_ENDED:
                print(f"{label}: the run ended after {link.ticks} ticks", file=sys.stderr)
                return 0
            print(f"{label}: the world fell silent after {link.ticks} ticks", file=sys.stderr)
            return 1
    except BridgeError as e:
        print(f"{label}: {e}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print(f"{label}: interrupted", file=sys.stderr)
        return 130
