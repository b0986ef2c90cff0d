"""Thermal logs: the canonical tidy format, reading wide files by column map, validation.

Canonical log (long format, one row per actuator and sample), CSV or Parquet:

==============  =======================  ==========
column          unit                     required
==============  =======================  ==========
``time``        s                        yes
``actuator``    name                     yes
``effort``      N m (rotary) or N        yes
``temperature`` degC, as measured        yes
``velocity``    rad/s or m/s             no
``current``     A                        no
``ambient``     degC                     no
==============  =======================  ==========

A single-actuator wide file (for instance a motor test bench's CSV) is read by
naming its columns, ``mapping={"effort": "torque", "temperature": "stator_winding", ...}``.
Every problem with a file raises :class:`LogError` with one sentence naming the
file, the column and what is expected.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Mapping

import numpy as np
import pandas as pd

from .model.signals import Signals

REQUIRED = ("time", "actuator", "effort", "temperature")
OPTIONAL = ("velocity", "current", "ambient")
UNITS = {"time": "s", "effort": "N m or N", "temperature": "degC", "velocity": "rad/s or m/s",
         "current": "A", "ambient": "degC"}
VELOCITY_UNITS = {"rad/s": 1.0, "m/s": 1.0, "rpm": 2.0 * np.pi / 60.0, "deg/s": np.pi / 180.0}
MIN_SAMPLES = 20


class LogError(ValueError):
    """A log cannot be used; the message says which file, which column and what is expected."""


@dataclass(frozen=True)
class ActuatorSeries:
    """One thermal channel of a log: its inputs and its measured temperature."""

    actuator: str
    signals: Signals
    temperature_C: np.ndarray

    @property
    def time_s(self) -> np.ndarray:
        return self.signals.time_s

    @property
    def n(self) -> int:
        return self.signals.n

    def rate_K_per_s(self, at_end: bool = False, window_s: float = 60.0) -> float:
        """Slope of the measured temperature over the first (or last) ``window_s`` seconds (least squares)."""
        t = self.time_s
        sel = t >= t[-1] - window_s if at_end else t <= t[0] + window_s
        if sel.sum() < 3:
            return 0.0
        return float(np.polyfit(t[sel] - t[sel][0], self.temperature_C[sel], 1)[0])

    def slice(self, start: int, stop: int) -> "ActuatorSeries":
        return ActuatorSeries(self.actuator, self.signals.slice(start, stop), self.temperature_C[start:stop])

    def split(self, fraction: float) -> tuple["ActuatorSeries", "ActuatorSeries"]:
        """Split by time span: training is the first ``fraction`` of it, validation the rest.

        The validation part starts at the last training sample, so that its
        free-run simulation starts from the measured temperature at the split.
        """
        if not 0.0 < fraction < 1.0:
            raise ValueError(f"split fraction must be between 0 and 1, got {fraction}")
        t = self.time_s
        cut = int(np.searchsorted(t, t[0] + fraction * (t[-1] - t[0]), side="right"))
        if cut < MIN_SAMPLES or self.n - cut < MIN_SAMPLES // 2:
            raise LogError(
                f"actuator {self.actuator}: {self.n} samples are too few to split at {fraction:.2f} "
                f"(need at least {MIN_SAMPLES} for training and {MIN_SAMPLES // 2} for validation)"
            )
        return self.slice(0, cut), self.slice(cut - 1, self.n)


@dataclass(frozen=True)
class ThermalLog:
    """A validated log in canonical long format (``frame`` sorted by actuator, then time)."""

    frame: pd.DataFrame
    source: str = "<memory>"

    @property
    def actuators(self) -> tuple[str, ...]:
        return tuple(pd.unique(self.frame["actuator"]))

    @property
    def columns(self) -> tuple[str, ...]:
        return tuple(c for c in REQUIRED + OPTIONAL if c in self.frame.columns)

    def series(self, actuator: str) -> ActuatorSeries:
        """The channel of one actuator; its neighbours are the actuators before and after it in the log's order."""
        if actuator not in self.actuators:
            raise LogError(f"{self.source}: no actuator {actuator!r}; the log has {', '.join(self.actuators)}")
        groups = {name: g for name, g in self.frame.groupby("actuator", sort=False)}
        g = groups[actuator]
        t = g["time"].to_numpy(float)

        def col(name):
            return g[name].to_numpy(float) if name in g.columns else None

        order = self.actuators
        i = order.index(actuator)
        others = [order[j] for j in (i - 1, i + 1) if 0 <= j < len(order)]
        neighbors = None
        if others:
            neighbors = np.column_stack([
                np.interp(t, groups[o]["time"].to_numpy(float), groups[o]["temperature"].to_numpy(float))
                for o in others
            ])
        signals = Signals(
            time_s=t, effort=col("effort"), velocity=col("velocity"), current_A=col("current"),
            ambient_C=col("ambient"), neighbor_temperature_C=neighbors, neighbor_names=tuple(others),
        )
        return ActuatorSeries(actuator, signals, col("temperature"))

    def write(self, path: str | Path) -> Path:
        """Write CSV or Parquet (by suffix), whole or not at all."""
        path = Path(path)
        kind = _kind(path)
        tmp = path.with_name(path.name + ".partial")
        path.parent.mkdir(parents=True, exist_ok=True)
        if kind == "csv":
            self.frame.to_csv(tmp, index=False)
        else:
            self.frame.to_parquet(tmp, index=False)
        tmp.replace(path)
        return path


def _kind(path: Path) -> str:
    suffix = path.suffix.lower()
    if suffix == ".csv":
        return "csv"
    if suffix in (".parquet", ".pq"):
        return "parquet"
    raise LogError(f"{path}: unknown log format {suffix!r}; expected .csv or .parquet")


def parse_mapping(text: str | None) -> dict[str, str]:
    """Parse ``"effort=torque,temperature=stator_winding"`` into ``{"effort": "torque", ...}``."""
    if not text:
        return {}
    mapping = {}
    for item in text.split(","):
        if "=" not in item:
            raise LogError(f"--map item {item!r} is not of the form canonical=column, e.g. effort=torque")
        key, value = (s.strip() for s in item.split("=", 1))
        if key not in REQUIRED + OPTIONAL:
            raise LogError(f"--map names {key!r}, which is not a log column; map any of: {', '.join(REQUIRED + OPTIONAL)}")
        mapping[key] = value
    return mapping


def read_log(
    path: str | Path,
    mapping: Mapping[str, str] | None = None,
    velocity_unit: str = "rad/s",
    actuator_name: str | None = None,
) -> ThermalLog:
    """Read and validate a log.

    Parameters
    ----------
    mapping
        For wide files: canonical name -> column in the file.  Without an
        ``actuator`` entry the file is one actuator named ``actuator_name``
        (default: the file's stem).
    velocity_unit
        Unit of the velocity column: ``rad/s``, ``m/s``, ``rpm`` or ``deg/s``;
        converted to rad/s (m/s stays m/s).
    """
    path = Path(path)
    kind = _kind(path)
    if not path.is_file():
        raise LogError(f"{path}: no such file")
    try:
        frame = pd.read_csv(path) if kind == "csv" else pd.read_parquet(path)
    except (ValueError, OSError, pd.errors.ParserError) as exc:
        raise LogError(f"{path}: cannot be read as {kind}: {exc}") from None
    return from_frame(frame, source=str(path), mapping=mapping, velocity_unit=velocity_unit,
                      actuator_name=actuator_name or path.stem)


def from_frame(
    frame: pd.DataFrame,
    source: str = "<memory>",
    mapping: Mapping[str, str] | None = None,
    velocity_unit: str = "rad/s",
    actuator_name: str = "actuator",
) -> ThermalLog:
    """Validate a data frame (canonical, or wide with ``mapping``) into a :class:`ThermalLog`."""
    mapping = dict(mapping or {})
    if velocity_unit not in VELOCITY_UNITS:
        raise LogError(f"unknown velocity unit {velocity_unit!r}; expected one of {', '.join(VELOCITY_UNITS)}")
    if mapping:
        absent = {k: v for k, v in mapping.items() if v not in frame.columns}
        if absent:
            k, v = next(iter(absent.items()))
            raise LogError(
                f"{source}: --map {k}={v} names column {v!r}, which the file does not have; "
                f"its columns are {', '.join(map(str, frame.columns))}"
            )
        unmapped = [c for c in REQUIRED if c != "actuator" and c not in mapping]
        if unmapped:
            raise LogError(
                f"{source}: --map does not name the column(s) for {', '.join(unmapped)}; add "
                f"{','.join(c + '=COLUMN' for c in unmapped)} with COLUMN among {', '.join(map(str, frame.columns))}"
            )
        frame = pd.DataFrame({k: frame[v] for k, v in mapping.items()})
        if "actuator" not in frame.columns:
            frame["actuator"] = actuator_name
    missing = [c for c in REQUIRED if c not in frame.columns]
    if missing:
        hint = "" if mapping else "; name them with --map canonical=column"
        raise LogError(
            f"{source}: missing column(s) {', '.join(missing)} (expected {', '.join(REQUIRED)}); "
            f"the file has {', '.join(map(str, frame.columns))}{hint}"
        )
    keep = [c for c in REQUIRED + OPTIONAL if c in frame.columns]
    frame = frame[keep].copy()
    frame["actuator"] = frame["actuator"].astype(str)
    for c in keep:
        if c == "actuator":
            continue
        values = pd.to_numeric(frame[c], errors="coerce")
        bad = values.isna() & frame[c].notna()
        if bad.any():
            row = int(np.flatnonzero(bad.to_numpy())[0])
            raise LogError(f"{source}: column {c!r} is not numeric at row {row} ({frame[c].iloc[row]!r}); expected {UNITS[c]}")
        frame[c] = values.astype(float)
        nan = ~np.isfinite(frame[c].to_numpy())
        if nan.any():
            row = int(np.flatnonzero(nan)[0])
            raise LogError(
                f"{source}: column {c!r} has {int(nan.sum())} missing or non-finite value(s), "
                f"first at row {row}; expected finite numbers in {UNITS[c]} (drop or fill those rows)"
            )
    if "velocity" in frame.columns:
        frame["velocity"] *= VELOCITY_UNITS[velocity_unit]
    parts = []
    for name, g in frame.groupby("actuator", sort=False):
        t = g["time"].to_numpy()
        steps = np.diff(t)
        if np.any(steps <= 0):
            k = int(np.flatnonzero(steps <= 0)[0])
            raise LogError(
                f"{source}: time does not increase for actuator {name!r} at row {g.index[k + 1]} "
                f"(t = {t[k]:g} s then {t[k + 1]:g} s); expected strictly increasing time in seconds"
            )
        if len(g) < MIN_SAMPLES:
            raise LogError(f"{source}: actuator {name!r} has {len(g)} samples; at least {MIN_SAMPLES} are needed")
        parts.append(g)
    if not parts:
        raise LogError(f"{source}: the log has no rows")
    return ThermalLog(pd.concat(parts, ignore_index=True), source)


def log_from_arrays(
    time_s: np.ndarray,
    names: tuple[str, ...],
    effort: np.ndarray,
    temperature_C: np.ndarray,
    velocity: np.ndarray | None = None,
    current_A: np.ndarray | None = None,
    ambient_C: np.ndarray | None = None,
    source: str = "<memory>",
) -> ThermalLog:
    """Build a canonical log from ``(n_samples, n_actuators)`` arrays (``ambient_C``: ``(n_samples,)``)."""
    n, m = effort.shape
    data = {
        "time": np.tile(time_s, m),
        "actuator": np.repeat(np.asarray(names, dtype=object), n),
        "effort": effort.T.ravel(),
        "temperature": temperature_C.T.ravel(),
    }
    if velocity is not None:
        data["velocity"] = velocity.T.ravel()
    if current_A is not None:
        data["current"] = current_A.T.ravel()
    if ambient_C is not None:
        data["ambient"] = np.tile(ambient_C, m)
    return from_frame(pd.DataFrame(data), source=source)
