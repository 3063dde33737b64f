"""`shoal.run`: what ``shoal run`` does, as a function.

The same world loader and options, the same run driver and so the same files in the same
folder (``out/<world name>`` unless ``out`` is given): ``summary.json``, ``trajectories.csv``,
``vehicles.csv``, the plots, ``replay.html`` and, with ``mcap=True``, ``run.mcap``.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from os import PathLike
from pathlib import Path

from ._shoal import run as _run


@dataclass(frozen=True)
class RunResult:
    """A finished run: its folder, how it ended and what ``summary.json`` says."""

    #: The output folder (absolute).
    out: Path
    #: ``"complete"`` (every planned step ran) or ``"agents-stopped"``.
    ending: str
    #: The content of ``summary.json`` (the numbers ``shoal run`` prints).
    summary: dict


def run(
    world: str | PathLike | None = None,
    out: str | PathLike | None = None,
    *,
    seed: int | None = None,
    duration: float | None = None,
    threads: int | None = None,
    plots: bool | None = None,
    replay: bool | None = None,
    mcap: bool | None = None,
    quiet: bool = False,
) -> RunResult:
    """Run a world as ``shoal run`` does and write its outputs.

    ``world`` is a world file's path or the TOML text of a world (``None``: the embedded
    default world). ``seed``, ``duration`` [s], ``plots``, ``replay`` and ``mcap`` change
    the world's own settings, checked with the world file's ranges (``None`` keeps the
    file's); ``threads`` is 1 … 256 (``None``: every core). Progress lines go to stderr
    unless ``quiet``.

    Raises :class:`shoal.WorldError` for a world or an option that cannot be (naming the
    line, field or keyword and the allowed range) and for worlds whose vehicles external
    agents drive; :class:`shoal.SimulationError` when a vehicle's state stops being finite
    and ``KeyboardInterrupt`` on Ctrl-C — both after the outputs up to that step are written.
    """
    ending, folder = _run(
        world,
        None if out is None else Path(out),
        seed=seed,
        duration=duration,
        threads=threads,
        plots=plots,
        replay=replay,
        mcap=mcap,
        quiet=quiet,
    )
    folder = Path(folder).resolve()
    summary = json.loads((folder / "summary.json").read_text())
    return RunResult(out=folder, ending=ending, summary=summary)
