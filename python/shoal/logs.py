"""``shoal.read_log``: one measured run read as ``shoal validate`` reads it — a CSV
(docs/validation.md), or a rosbag2 (an ``.mcap`` file or a rosbag2 folder) through a mapping
TOML — and handed back as numpy columns, without a search: to plot a bag, check what a mapping
makes of it, or hand the columns to :func:`shoal.validate` after editing them.

A bag's run is what the validation sees: its rows are the union of the mapped topics' sample
times, counted from the moment every input and reference has had its first message (earlier
samples are dropped); inputs and references are held from one message to the next; a channel
has numbers at its own samples only and NaN at the other rows; depth, attitude and rates in shoal's frames
(north-east-down, body forward-right-down). Gaps in time are not split here.

Errors: :class:`shoal.ValidationError` naming the file, line and column (or topic and field),
or the mapping file (``setting == "mapping"``).
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Optional, Union

import numpy as np

from . import _shoal

__all__ = ["Log", "read_log"]


@dataclass(frozen=True)
class Log:
    """A measured run: ``columns`` maps the CSV format's names to 1-D arrays — ``t`` [s: a
    CSV's own times; a bag's from the run's start], each input ``u.NAME`` (the value in force
    at every row: % for thrusters, rad for tilt drives, −1/0/+1 for the pump), each channel
    ``y.NAME`` (SI, angles in radians; NaN where not sampled), each reference of the vehicle's
    controller ``r.NAME`` (held as the inputs are: ``r.depth`` [m, positive down], ``r.yaw``
    [rad], ``r.surge`` and ``r.sway`` [N], ``r.mode`` the mode's code 0 off … 5 auto, 6 raw)."""

    #: The run's name (the file's stem).
    name: str
    #: How it was read (rows, format, topics), as ``shoal validate`` reports it.
    source: str
    #: Column name → values, ``t`` first, then the inputs, the channels, the references.
    columns: dict

    @property
    def t(self) -> np.ndarray:
        """Time of each row [s]."""
        return self.columns["t"]

    def samples(self, channel: str) -> tuple:
        """``(t, values)`` of the rows at which ``channel`` (e.g. ``"y.depth"``) was sampled."""
        v = self.columns[channel]
        keep = ~np.isnan(v)
        return self.t[keep], v[keep]


def read_log(
    path: Union[str, "os.PathLike[str]"],
    *,
    mapping: Union[str, "os.PathLike[str]", None] = None,
    time_unit: Optional[str] = None,
) -> Log:
    """Reads the log at ``path`` (a CSV, or a rosbag2 through ``mapping``); ``time_unit``
    (``"s"`` or ``"ms"``) is the unit of a plain ``t`` column. Returns a :class:`Log`."""
    name, source, cols = _shoal.read_log(
        os.fspath(path), None if mapping is None else os.fspath(mapping), time_unit
    )
    return Log(name=name, source=source, columns=dict(cols))
