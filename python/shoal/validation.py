"""``shoal.validate`` (this module: ``shoal.validation``): what the simulation gets wrong on measured runs, the effects that explain
it, the fitted vehicle and its gain on data it did not fit — ``shoal validate`` as a function.

Runs are paths of logs — CSV (docs/validation.md), or rosbag2s (an ``.mcap`` file or a rosbag2
folder) read through ``mapping=``, a mapping TOML as ``shoal validate --mapping`` takes; each
file is recognised by its content — or columns of numbers: a mapping from the CSV
format's column names (``t``, ``u.top``, …, ``y.depth``, …) to 1-D arrays (a ``dict`` of numpy
arrays, a pandas ``DataFrame``, …), optionally named as ``(name, columns)``. The search runs
with the GIL released (Ctrl-C raises ``KeyboardInterrupt``); by default progress is reported on
stderr as ``shoal validate`` reports it (``quiet=True`` silences it); ``progress(kind, message)``
instead hears of every file read (``read``),
inputs clamped to the vehicle's limits (``clamped``), the start (``start``), each stage of the
search as it begins (``stage``, with its number of fits when known) and every fit (``fit``).

Errors: :class:`shoal.ValidationError` (a ``ValueError``) with attributes ``setting`` (the
keyword argument at fault), ``file``, ``line`` and ``column`` (the run at fault; for columns
given in memory line 1 is the header and line k + 2 the row k).
"""

from __future__ import annotations

import json
import os
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Iterable, Mapping, Optional, Sequence, Union

import numpy as np

from . import _shoal

__all__ = ["Channel", "Effect", "Parameter", "Report", "validate"]

Run = Union[str, "os.PathLike[str]", Mapping[str, Any], "tuple[str, Mapping[str, Any]]"]


@dataclass(frozen=True)
class Parameter:
    """A fitted parameter of a named effect (value in ``unit``; SI, angles in radians)."""

    name: str
    unit: str
    value: float
    #: Standard deviation (None where it could not be estimated).
    sigma: Optional[float]
    #: 95 % confidence interval (low, high), or None.
    ci95: Optional[tuple[float, float]]


@dataclass(frozen=True)
class Effect:
    """An effect the validation names: its family, the form that fits best, its parameters
    and how often it was selected over block-bootstrap resamples (0…1)."""

    name: str
    form: str
    parameters: list[Parameter]
    stability: Optional[float]
    explanation: str


@dataclass(frozen=True)
class Channel:
    """One measured channel (``y.depth`` …): held-out RMSE (in the channel's unit) and NRMSE
    fit [%] of the baseline and of the extended model, and whether their residuals are white
    (Ljung–Box at 5 %)."""

    rmse_before: float
    rmse_after: float
    gain_pct: float
    fit_pct_before: float
    fit_pct_after: float
    white_before: bool
    white_after: bool


@dataclass(frozen=True)
class Report:
    """The outcome of :func:`validate`.

    ``verdict`` is the one-sentence summary; ``effects`` the named effects; ``channels`` the
    before/after table by channel; ``possible``, ``ambiguous`` and ``unexplained`` the weaker
    findings as in ``report.json`` (an "A or B" with ``inclusion``, its two families' shares of the
    resamples, and ``across_resamples`` when the resamples found it); ``inclusion`` P(family):
    for each named effect, each effect left possible and each family tried in its place, the
    share (0…1) of the block-bootstrap resamples on which it holds the place; ``validation_gain_pct`` the headline, the mean of the
    channels' ``gain_pct``; ``changed_channels`` the channels the model changes (by at least
    their sensor's resolution) and ``changed_channels_gain_pct`` the mean gain over them;
    ``data`` the whole of ``report.json``; ``vehicle_toml`` the
    fitted vehicle as a world file (run it with ``shoal run``); ``next_experiment`` the
    suggested flight when the log leaves a question open (an "A or B", an effect only
    possible: its manoeuvre and each question's separation on the log and predicted for the
    flight, as in ``report.json``), else ``None``, and ``next_experiment_toml`` that flight as
    a world file. :meth:`write` writes the usual files (``report.json``, ``report.md``,
    ``vehicle.toml``, ``next_experiment.toml`` when there is one, plots).
    """

    verdict: str
    effects: list[Effect]
    channels: dict[str, Channel]
    possible: list[dict]
    ambiguous: list[dict]
    unexplained: list[dict]
    inclusion: dict[str, float]
    validation_gain_pct: float
    changed_channels: list[str]
    changed_channels_gain_pct: float
    data: dict = field(repr=False)
    vehicle_toml: str = field(repr=False)
    next_experiment: Optional[dict] = None
    next_experiment_toml: Optional[str] = field(repr=False, default=None)
    _native: Any = field(repr=False, compare=False, default=None)

    @property
    def effect_names(self) -> list[str]:
        """The names of the effects found, in the order they were chosen."""
        return [e.name for e in self.effects]

    def write(self, directory: Union[str, "os.PathLike[str]"], plots: bool = True) -> dict:
        """Writes ``report.json``, ``report.md``, ``vehicle.toml`` and (with ``plots``) the
        plots into ``directory`` (created if missing); returns their paths."""
        js, md, vehicle, nxt, pngs = self._native.write(Path(directory), plots)
        return {
            "json": js,
            "markdown": md,
            "vehicle": vehicle,
            "next_experiment": nxt,
            "plots": pngs,
        }


def _run_arg(run: Run, i: int, what: str):
    if isinstance(run, (str, os.PathLike)):
        return os.fspath(run)
    if isinstance(run, tuple) and len(run) == 2 and isinstance(run[0], str):
        name, columns = run
    elif hasattr(run, "items"):
        name, columns = f"{what}_{i + 1}", run
    else:
        raise TypeError(
            f"{what}[{i}]: expected a path, a mapping of columns or (name, columns), "
            f"not {type(run).__name__}"
        )
    cols = [(str(k), np.asarray(v, dtype=np.float64)) for k, v in columns.items()]
    if not name.endswith(".csv"):
        name += ".csv"
    return (name, cols)


def _runs(runs: Union[Run, Sequence[Run], None], what: str) -> list:
    if runs is None:
        return []
    if isinstance(runs, (str, os.PathLike, tuple)) or hasattr(runs, "items"):
        runs = [runs]
    return [_run_arg(r, i, what) for i, r in enumerate(runs)]


def _names(v: Union[str, Iterable[str], None]) -> list[str]:
    if v is None:
        return []
    if isinstance(v, str):
        return [s for s in v.split(",") if s]
    return [str(s) for s in v]


class _StderrProgress:
    """Progress on stderr as ``shoal validate`` prints it: files read, clamped inputs, the start,
    each stage, and every 10th fit of a stage (``kind`` and ``message`` as ``progress`` hears
    them)."""

    def __init__(self) -> None:
        self.fits = 0

    def __call__(self, kind: str, message: str) -> None:
        if kind == "fit":
            self.fits += 1
            if self.fits % 10 == 0:
                print(f"  {self.fits} fits, last: {message}", file=sys.stderr, flush=True)
            return
        if kind == "stage":
            self.fits = 0
        prefix = "  " if kind == "clamped" else "shoal: "
        word = "read " if kind == "read" else ""
        print(f"{prefix}{word}{message}", file=sys.stderr, flush=True)


def validate(
    runs: Union[Run, Sequence[Run]],
    holdout: Union[Run, Sequence[Run], None] = None,
    *,
    vehicle: Union[str, "os.PathLike[str]", None] = None,
    channels: Union[str, Iterable[str], None] = None,
    effects: Union[str, Iterable[str], None] = None,
    split: float = 0.6,
    dt: float = 0.01,
    time_unit: Optional[str] = None,
    gaps: str = "split",
    max_gap: Optional[float] = None,
    min_segment: float = 1.0,
    threads: Optional[int] = None,
    progress: Optional[Callable[[str, str], Any]] = None,
    horizon: Union[str, float] = "choose",
    mapping: Union[str, "os.PathLike[str]", None] = None,
    quiet: bool = False,
) -> Report:
    """Validates a vehicle model against measured runs, as ``shoal validate`` does.

    ``runs`` are fitted on (without ``holdout`` each is split: the first ``split`` of it for
    estimation, the rest for validation); ``holdout`` runs are only scored. ``vehicle`` is a
    world file whose first vehicle group is the baseline (default: the μAUV² preset).
    ``channels`` (e.g. ``"y.r,y.depth"``) and ``effects`` restrict the measurements used and the
    effects considered. ``dt`` is the replay step [s] (1e-4 … 0.1); ``time_unit`` (``"s"`` or
    ``"ms"``) the unit of a plain ``t`` column; ``gaps`` (``"split"`` or ``"error"``), ``max_gap``
    [s] and ``min_segment`` [s] what a gap in time does; ``threads`` the worker threads of the
    search (results do not depend on it); ``horizon`` how runs are replayed: ``"choose"`` (the
    default: as ``"auto"`` for runs of 300 s or longer, else open loop), ``"closed"`` (as ``"auto"``, and beside each replay its closed-loop twin:
    the vehicle's controller following the log's ``r.`` references, its commands compared with
    the logged ones), ``"open"`` (open loop), a number of seconds (re-anchored to the measured
    depth, attitude and rates that often) or ``"auto"`` (a horizon chosen from the data). ``mapping`` is the mapping TOML through which rosbag2s among the runs are read (which
    topic and field is each input and channel; docs/validation.md "Your rosbag2"). Progress goes
    to ``progress(kind, message)`` if given, else to stderr unless ``quiet``. Returns a
    :class:`Report`.
    """
    if progress is None and not quiet:
        progress = _StderrProgress()
    native = _shoal.validate(
        _runs(runs, "runs"),
        _runs(holdout, "holdout"),
        None if vehicle is None else os.fspath(vehicle),
        _names(channels),
        _names(effects),
        float(split),
        float(dt),
        time_unit,
        gaps,
        None if max_gap is None else float(max_gap),
        float(min_segment),
        threads,
        progress,
        str(horizon),
        None if mapping is None else os.fspath(mapping),
    )
    data = json.loads(native.report_json())
    v = data["verdict"]
    named = [
        Effect(
            name=e["effect"],
            form=e["form"],
            parameters=[
                Parameter(
                    name=p["name"],
                    unit=p["unit"],
                    value=p["value"],
                    sigma=p["sigma"],
                    ci95=None if p["ci95"] is None else tuple(p["ci95"]),
                )
                for p in e["params"]
            ],
            stability=e["stability"],
            explanation=v["explanations"].get(e["effect"], ""),
        )
        for e in v["named"]
    ]
    chans = {k: Channel(**c) for k, c in v["channels"].items()}
    return Report(
        verdict=v["summary"],
        effects=named,
        channels=chans,
        possible=v["possible"],
        ambiguous=v["ambiguous"],
        unexplained=v["unexplained"],
        inclusion=v["inclusion"],
        validation_gain_pct=v["validation_gain_pct"],
        changed_channels=v["changed_channels"],
        changed_channels_gain_pct=v["changed_channels_gain_pct"],
        data=data,
        vehicle_toml=native.vehicle_toml(),
        next_experiment=v["next_experiment"],
        next_experiment_toml=native.next_experiment_toml(),
        _native=native,
    )
