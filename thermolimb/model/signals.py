"""The inputs a thermal model sees for one actuator, as plain arrays."""

from __future__ import annotations

from dataclasses import dataclass, field, fields, replace
from functools import cached_property
from typing import Mapping

import numpy as np

from .scan import CONSTANT_A, Recursion

FEW_LEVELS = 8  # intervals of at most n / 8 distinct lengths are looked up, not exponentiated one by one
LOOKUP_FROM = 256  # intervals: fewer are exponentiated one by one
# the constant rates' recursions kept per signals (Signals.recursion)
RECURSIONS, RECURSION_BYTES = 8, 64 << 20
EXTRA = "extra."  # a term needing an extra channel names it "extra.NAME" in its columns

# log column -> Signals attribute (the optional input channels a term may need)
CHANNELS = {
    "effort": "effort",
    "velocity": "velocity",
    "current": "current_A",
    "power": "power_W",
    "ambient": "ambient_C",
    "housing": "housing_C",
    "neighbors": "neighbor_temperature_C",
}


@dataclass(frozen=True)
class Signals:
    """Time series of one actuator, sampled at ``time_s``.

    Inputs are held constant over each sample interval (zero-order hold).
    Optional channels are ``None`` when the log does not have them.
    """

    time_s: np.ndarray
    effort: np.ndarray  # N m (rotary) or N (linear)
    velocity: np.ndarray | None = None  # rad/s or m/s
    current_A: np.ndarray | None = None
    ambient_C: np.ndarray | None = None
    neighbor_temperature_C: np.ndarray | None = None  # (n, m): the other actuators' measured temperatures
    neighbor_names: tuple[str, ...] = field(default=())
    housing_C: np.ndarray | None = None  # a second measured temperature: housing, case or driver board
    power_W: np.ndarray | None = None  # electrical input power
    # channels the log carries beyond these, by name
    extra: Mapping[str, np.ndarray] = field(default_factory=dict)
    # K the run's temperatures (winding, ambient, housing, neighbours) were moved down to the air of the runs
    # it is fitted with (:func:`~thermolimb.model.experience.common_air`): what reads an absolute temperature
    # adds it back
    air_shift_K: float = 0.0

    def __post_init__(self):
        for name in ("time_s",) + tuple(CHANNELS.values()):  # lists and tuples are taken as arrays
            value = getattr(self, name, None)
            if value is not None and not isinstance(value, np.ndarray):
                object.__setattr__(self, name, np.asarray(value, float))
        if self.time_s.ndim != 1:
            raise ValueError(f"Signals.time_s must be one-dimensional (s), got shape {self.time_s.shape}")
        back = np.flatnonzero(np.diff(self.time_s) < 0)
        if back.size:
            k = int(back[0])
            raise ValueError(f"Signals.time_s goes back at sample {k + 1} ({self.time_s[k]:g} s, then "
                             f"{self.time_s[k + 1]:g} s); time must not decrease")
        n = self.time_s.shape[0]
        arrays = [(name, getattr(self, name)) for name in CHANNELS.values()]
        for name, value in arrays + [(f"extra[{k!r}]", v) for k, v in self.extra.items()]:
            if value is not None and value.shape[0] != n:
                raise ValueError(f"Signals.{name} has {value.shape[0]} samples, time_s has {n}")

    @property
    def n(self) -> int:
        return int(self.time_s.shape[0])

    @cached_property
    def dt_s(self) -> np.ndarray:
        """Interval lengths, ``n - 1`` of them (computed once: the arrays are not changed after
        construction)."""
        return np.diff(self.time_s)

    @cached_property
    def median_dt_s(self) -> float:
        """The median sampling interval (s), worked out once (a long log's replicates asked it 20 times: 0.2
        s)."""
        dt = self.__dict__.get("dt_s")
        return float(np.median(np.diff(self.time_s) if dt is None else dt))

    @cached_property
    def uniform_dt_s(self) -> float | None:
        """The one sampling interval when every interval equals it to rounding (``CONSTANT_A``), else
        ``None``. The intervals are not kept for this: a uniform log needs only its one step."""
        dt = self.__dict__.get("dt_s")
        dt = np.diff(self.time_s) if dt is None else dt
        if dt.size == 0:
            return None
        step = float(dt.mean())
        return step if step > 0.0 and float(dt.max() - dt.min()) <= CONSTANT_A * step else None

    @cached_property
    def interval_levels(self) -> tuple[np.ndarray, np.ndarray] | None:
        """``(levels, index)``: the distinct intervals and each interval's among them, when they are few (a
        log timed to the millisecond: the UR3's 7354 intervals take 228 lengths); else ``None``."""
        dt = self.dt_s
        if dt.size < LOOKUP_FROM:  # a monitor's piece of a sample or two: sorting costs more than it saves
            return None
        levels, index = np.unique(dt, return_inverse=True)
        return (levels, index.astype(np.int32)) if levels.size <= dt.size // FEW_LEVELS else None

    def recursion(self, rate_per_s: float | np.ndarray) -> Recursion:
        """The factors ``a = exp(-rate_per_s * dt)`` of each interval made ready for scans
        (:class:`~thermolimb.model.scan.Recursion`).  A constant rate's are kept: a simulation's coupling
        passes and a fit's evaluations ask for the same rates again (``RECURSIONS`` of them,
        ``RECURSION_BYTES`` at most). At a constant rate, an exponential per distinct interval when they are
        few (it costs more than the scan it feeds); a rate per sample holds over the interval it starts."""
        if np.ndim(rate_per_s):
            log_a = -rate_per_s[:-1] * self.dt_s
            return Recursion(np.exp(log_a), log_a)
        kept = self.__dict__.setdefault("_recursions", {})
        found = kept.pop(rate_per_s, None)
        if found is None:
            dt = self.interval_s
            log_a = -rate_per_s * dt
            levels = self.interval_levels if np.ndim(dt) else None
            found = Recursion(np.exp(log_a) if levels is None else np.exp(-rate_per_s * levels[0])[levels[1]],
                              log_a)
            while kept and (len(kept) >= RECURSIONS or sum(r.nbytes for r in kept.values()) + found.nbytes >
                            RECURSION_BYTES):
                kept.pop(next(iter(kept)))  # the least recently used
        kept[rate_per_s] = found  # the most recent last
        return found

    def __getstate__(self):
        """What pickles: the signals, not the recursions kept for them (a pool's job would carry them)."""
        return {k: v for k, v in self.__dict__.items() if k != "_recursions"}

    @cached_property
    def neighbor_mean_C(self) -> np.ndarray:
        """The neighbours' mean measured temperature per sample (computed once)."""
        return self.channel("neighbors").mean(axis=1)

    @property
    def interval_s(self) -> np.ndarray | float:
        """The sampling interval: one number when the log is uniformly sampled, else :attr:`dt_s`."""
        return self.dt_s if self.uniform_dt_s is None else self.uniform_dt_s

    def has(self, name: str) -> bool:
        """Whether the log column ``name`` is present (``extra.NAME`` for an extra channel)."""
        if name.startswith(EXTRA):
            return name[len(EXTRA):] in self.extra
        return getattr(self, CHANNELS[name]) is not None

    def channel(self, name: str) -> np.ndarray:
        """A channel by its log column name (``extra.NAME`` for an extra one), with an error naming what is
        missing."""
        value = self.extra.get(name[len(EXTRA):]) if name.startswith(EXTRA) else getattr(self, CHANNELS[name])
        if value is None:
            raise KeyError(f"this model needs the '{name}' column, which the log does not have")
        return value

    def contribution(self, term, params) -> tuple[np.ndarray | float, np.ndarray | float]:
        """``term``'s ``(rise, gain)`` on these signals (a block-averaged run, :mod:`.block_means`, averages
        them)."""
        return term.contribution(params, self)

    def map_arrays(self, fn) -> "Signals":
        """The same signals with ``fn`` applied to the time axis and every channel present."""
        changed = {
            f.name: fn(getattr(self, f.name))
            for f in fields(self)
            if f.name not in ("neighbor_names", "extra", "air_shift_K") and getattr(self, f.name) is not None
        }
        changed["extra"] = {k: fn(v) for k, v in self.extra.items()}
        return replace(self, **changed)

    def slice(self, start: int, stop: int, step: int = 1) -> "Signals":
        return self.map_arrays(lambda x: x[start:stop:step])
