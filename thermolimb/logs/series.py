"""A thermal log's data: one actuator's series and runs, and the validated log of several actuators.

Reading a file into a :class:`ThermalLog` is :mod:`.reading`'s; validating a
frame, :mod:`.validate`'s; writing one, :mod:`.writing`'s.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from functools import cached_property
from pathlib import Path
from typing import Mapping

import numpy as np

from ..model.signals import Signals
from ..util.errors import LogError
from ..util.frozen import FrozenMapping
from ..util.lazy import pandas as pd
from .mapping import EXTRA, OPTIONAL, REQUIRED
from .units import CANONICAL
from .writing import write_log

CANONICAL_UNITS = FrozenMapping(CANONICAL)

MIN_SAMPLES = 20
# A pause in logging longer than this many sampling intervals (and than GAP_MIN_S) splits a log into runs.
GAP_FACTOR = 20.0
GAP_MIN_S = 60.0


@dataclass(frozen=True)
class ActuatorSeries:
    """One thermal channel of a log (or of one run of it): its inputs and its measured temperature."""

    actuator: str
    signals: Signals
    temperature_C: np.ndarray
    run: str = ""
    # of effort, velocity, current, power (see thermolimb.logs.units)
    units: Mapping[str, str] = CANONICAL_UNITS
    # the samples a fit compares (a validation scheme that holds blocks out of the run); None: all of them
    fit_mask: np.ndarray | None = field(default=None, repr=False)

    @property
    def time_s(self) -> np.ndarray:
        return self.signals.time_s

    @property
    def n(self) -> int:
        return self.signals.n

    @property
    def duration_s(self) -> float:
        return float(self.time_s[-1] - self.time_s[0])

    @property
    def median_dt_s(self) -> float:
        return self.signals.median_dt_s

    def rate_K_per_s(self, at_end: bool = False, window_s: float = 60.0) -> float:
        """Slope of the measured temperature over the first (or last) ``window_s`` seconds (least squares)."""
        t = self.time_s
        if at_end:
            sel = slice(int(np.searchsorted(t, t[-1] - window_s, side="left")), None)
        else:
            sel = slice(0, int(np.searchsorted(t, t[0] + window_s, side="right")))
        if t[sel].size < 3:
            return 0.0
        return float(np.polyfit(t[sel] - t[sel][0], self.temperature_C[sel], 1)[0])

    def slice(self, start: int, stop: int, step: int = 1) -> "ActuatorSeries":
        mask = None if self.fit_mask is None else self.fit_mask[start:stop:step]
        return replace(self, signals=self.signals.slice(start, stop, step),
                       temperature_C=self.temperature_C[start:stop:step], fit_mask=mask)

    @property
    def fit_samples(self) -> int:
        """How many samples a fit compares."""
        return self.n if self.fit_mask is None else int(np.count_nonzero(self.fit_mask))

    def split_index(self, fraction: float) -> int:
        """First sample after the first ``fraction`` of the time span (training is ``[0, index)``)."""
        if not 0.0 < fraction < 1.0:
            raise LogError(f"the split fraction must be between 0 and 1 (exclusive), got {fraction}")
        t = self.time_s
        cut = int(np.searchsorted(t, t[0] + fraction * (t[-1] - t[0]), side="right"))
        if cut < MIN_SAMPLES // 2 or self.n - cut < MIN_SAMPLES // 4:
            raise LogError(
                f"actuator {self.actuator}{self.run_label}: {self.n} "
                f"samples are too few to split at {fraction:.2f} "
                f"(need at least {MIN_SAMPLES // 2} for training and "
                f"{MIN_SAMPLES // 4} for validation); use a longer "
                f"log, several runs with --validate-on, or another --split"
            )
        return cut

    def split(self, fraction: float) -> tuple["ActuatorSeries", "ActuatorSeries"]:
        """Split by time span: training is the first ``fraction`` of it, validation the rest.

        The validation part starts at the last training sample, so that a
        free run restarted at the split starts from the measured temperature there.
        """
        cut = self.split_index(fraction)
        return self.slice(0, cut), self.slice(cut - 1, self.n)

    @property
    def run_label(self) -> str:
        return f" (run {self.run})" if self.run else ""


@dataclass(frozen=True)
class ThermalLog:
    """A validated log in canonical long format (``frame`` sorted by actuator, then time).

    ``notes`` says what reading changed: rows without a measurement dropped,
    timestamps turned into seconds.
    """

    frame: pd.DataFrame
    source: str = "<memory>"
    notes: tuple[str, ...] = field(default=())
    # of effort, velocity, current, power, from the log (logs.units)
    units: Mapping[str, str] = CANONICAL_UNITS
    # read for some actuators only (read_log(actuators=...)): every actuator of the file in its order, and the
    # (time s, temperature degC) of those beside a kept one, which a kept actuator's neighbour coupling reads
    # (none when read with neighbours=False: its series then have no neighbour temperatures)
    order: tuple[str, ...] = ()
    neighbours: Mapping[str, tuple] = FrozenMapping({})

    @cached_property
    def actuators(self) -> tuple[str, ...]:
        return tuple(pd.unique(self.frame["actuator"]))

    @cached_property
    def _groups(self) -> dict:
        """Each actuator's rows, split once (a log's frame is not changed after reading); a log of one
        actuator (read with ``actuators=``) is its own group, not a copy."""
        if len(self.actuators) == 1:
            return {self.actuators[0]: self.frame}
        return {name: g for name, g in self.frame.groupby("actuator", sort=False)}

    @property
    def columns(self) -> tuple[str, ...]:
        return tuple(c for c in REQUIRED + OPTIONAL if c in self.frame.columns)

    @cached_property
    def extras(self) -> tuple[str, ...]:
        """Names of the channels the log carries beyond the canonical ones (:mod:`.extras`); their units are
        in ``units`` as ``extra.NAME``."""
        return tuple(c[len(EXTRA):] for c in self.frame.columns if c.startswith(EXTRA))

    def arrays(self, actuator: str) -> dict[str, np.ndarray]:
        """One actuator's columns as float arrays, by their canonical names (``time``, ``effort``,
        ``temperature``, each optional channel the log has, each extra as ``extra.NAME``): its rows as read,
        no neighbour looked up (what a follower hands on, piece by piece)."""
        if actuator not in self.actuators:
            raise LogError(
                f"{self.source}: no actuator {actuator!r}; the log has {', '.join(self.actuators)}"
            )
        g = self._groups[actuator]
        return {c: g[c].to_numpy(float) for c in g.columns if c != "actuator"}

    def series(self, actuator: str) -> ActuatorSeries:
        """The channel of one actuator; its neighbours are the actuators before and after it in the log's
        order."""
        if actuator not in self.actuators:
            raise LogError(
                f"{self.source}: no actuator {actuator!r}; the log has {', '.join(self.actuators)}"
            )
        groups = self._groups
        g = groups[actuator]
        t = g["time"].to_numpy(float)

        def col(name):
            return g[name].to_numpy(float) if name in g.columns else None

        order = self.order or self.actuators
        i = order.index(actuator)
        # a neighbour whose reading never changes (a joint set aside as "nothing to learn") brings no heat to
        # read
        others = [order[j] for j in (i - 1, i + 1)
                  if 0 <= j < len(order) and (order[j] in groups or order[j] in self.neighbours)
                  and np.ptp(self._temperature_of(order[j])[1]) > 0]
        neighbors = None
        if others:
            neighbors = np.column_stack([np.interp(t, *self._temperature_of(o)) for o in others])
        signals = Signals(time_s=t, effort=col("effort"), velocity=col("velocity"), current_A=col("current"),
                          ambient_C=col("ambient"), neighbor_temperature_C=neighbors,
                          neighbor_names=tuple(others), housing_C=col("housing"), power_W=col("power"),
                          extra={name: col(EXTRA + name) for name in self.extras})
        return ActuatorSeries(actuator, signals, col("temperature"), units=self.units)

    def _temperature_of(self, name: str) -> tuple[np.ndarray, np.ndarray]:
        if name in self._groups:
            g = self._groups[name]
            return g["time"].to_numpy(float), g["temperature"].to_numpy(float)
        return self.neighbours[name]

    def runs(self, actuator: str) -> list[ActuatorSeries]:
        """The actuator's series cut at pauses in logging (see :func:`gaps`); each run starts from its own
        reading."""
        whole = self.series(actuator)
        cuts = gaps(whole.time_s)
        stem = Path(self.source).stem if self.source != "<memory>" else "log"
        if not cuts:  # named as a cut run would be, so that runs of several files stay apart
            return [replace(whole, run=f"{stem}#1")]
        edges = [0] + cuts + [whole.n]
        pieces = [whole.slice(a, b) for a, b in zip(edges[:-1], edges[1:])]
        return [replace(p, run=f"{stem}#{k + 1}") for k, p in enumerate(pieces) if p.n >= MIN_SAMPLES]

    def describe_gaps(self, actuator: str) -> str | None:
        """A sentence on the runs a log was cut into, or ``None``."""
        whole = self.series(actuator)
        cuts = gaps(whole.time_s)
        if not cuts:
            return None
        lengths = np.diff([0] + cuts + [whole.n])
        dropped = int(np.sum(lengths < MIN_SAMPLES))
        pauses = ", ".join(f"{whole.time_s[c] - whole.time_s[c - 1]:.0f} s at t = {whole.time_s[c - 1]:.0f} s"
                           for c in cuts)
        tail = f"; {dropped} run(s) shorter than {MIN_SAMPLES} samples left out" if dropped else ""
        return (f"{self.source}: actuator {actuator}: logging pauses "
                f"({pauses}) cut the log into {len(cuts) + 1} runs, "
                f"each simulated from its own first reading{tail}")

    def write(self, path: str | Path) -> Path:
        """Write CSV, Parquet or a ROS 2 MCAP file (by suffix), whole or not at all (:mod:`.writing`)."""

        return write_log(self, path)


def gaps(time_s: np.ndarray) -> list[int]:
    """Indices where a run starts after a pause longer than ``GAP_FACTOR`` median intervals and
    ``GAP_MIN_S``."""
    if time_s.size < 3:
        return []
    dt = np.diff(time_s)
    limit = max(GAP_FACTOR * float(np.median(dt)), GAP_MIN_S)
    return [int(k) + 1 for k in np.flatnonzero(dt > limit)]
