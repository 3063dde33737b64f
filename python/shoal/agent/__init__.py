"""shoal.agent: external swarm agents for the shoal simulator in Python, over iceoryx2 shared
memory (a world run by `shoal run` in another process). `protocol` holds the wire structs
(generated from the Rust ones); `agent` the link to a running world and helpers for commands
and frames. See python/README.md. (Formerly the package `shoal_agent`, which remains as an
alias.)
"""

from .agent import (
    Agent,
    AgentLink,
    AgentTaken,
    BridgeError,
    Ended,
    NoWorld,
    keep,
    main,
    received,
    run,
    send,
    service_name,
    set_mode,
)
from .protocol import (
    ALL_MODEMS,
    FRAME_BYTES,
    MAX_RX_FRAMES,
    MAX_THRUSTERS,
    MAX_TILTS,
    MAX_TX_FRAMES,
    PROTOCOL_VERSION,
    Command,
    Frame,
    Observation,
    flags,
    kind,
    mode,
)

__all__ = [
    "ALL_MODEMS",
    "Agent",
    "AgentLink",
    "AgentTaken",
    "BridgeError",
    "Command",
    "Ended",
    "FRAME_BYTES",
    "Frame",
    "MAX_RX_FRAMES",
    "MAX_THRUSTERS",
    "MAX_TILTS",
    "MAX_TX_FRAMES",
    "NoWorld",
    "Observation",
    "PROTOCOL_VERSION",
    "flags",
    "keep",
    "main",
    "kind",
    "mode",
    "received",
    "run",
    "send",
    "service_name",
    "set_mode",
]
