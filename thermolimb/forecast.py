"""How long until a joint reaches a temperature, from a saved model, with an interval a user can trust.

A forecast is a free run of the identified model from a known start (a log's first reading, a stated
temperature) under given inputs (a log's efforts and channels, or a plan held for a duration).  Its interval
combines the two ways the answer can be wrong:

* **the parameters** are uncertain: ``draws`` parameter vectors are drawn (seeded) from the blocked
  jackknife's covariance the model file stores (the model refitted with each fifth of the log left out;
  :func:`~thermolimb.workbench.saving.jackknife_covariance`), each simulated; their spread at each instant is
  one part of the band.  The fit's own covariance assumes the model is true and is several times too narrow on
  a plant richer than the model; the refits' spread is not;
* **the model** misses physics: a richer plant (a heavier housing, speed losses, copper's tempco) leaves an
  error the covariance knows nothing about, and which is far larger when the model is wrong (the covariance
  alone then gives a band a fraction of a kelvin wide around a curve several kelvin off).  The fit's held-out
  free-run residual measures it: its ``level`` quantile of |residual| is the half-width the model error
  reaches once the free run has forgotten its start.  A free run starts from a measured temperature, so the
  error starts at zero and grows as a first-order process does, ``sqrt(1 - exp(-2 t / RC))``; held-out data
  tell nothing about an input larger than the log's, so the error is also scaled by how far the forecast's
  rise exceeds the largest rise the held-out data saw (never below one).

The two half-widths add in quadrature (independent sources); the band is ``predicted ± half-width``.  The
time to the threshold is where the predicted curve first reaches it; its interval runs from where the upper
edge reaches it to where the lower edge does (``None`` when the lower edge never does within the horizon:
the interval is open).  ``benchmarks/forecast.py`` measures the coverage on plant logs richer than the model.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.special import ndtri  # the normal quantile (scipy.stats.norm.ppf is it, at ten times the import)

from .model.experience import beyond, hotter_than_seen, shifted
from .model.model import ThermalModel
from .model.reach import crossing_s
from .model.saved import SavedModel
from .model.signals import Signals
from .util.errors import ThermolimbError

LEVEL = 0.9
DRAWS = 64
PARAMETER_SPREAD = "fit"


@dataclass(frozen=True)
class Forecast:
    """A predicted temperature with its band, and when it first reaches ``threshold_C``."""

    actuator: str
    time_s: np.ndarray  # from the forecast's start
    predicted_C: np.ndarray
    low_C: np.ndarray
    high_C: np.ndarray
    threshold_C: float
    level: float
    start_C: float
    time_to_threshold_s: float | None  # None: the prediction does not reach it within the horizon
    interval_s: tuple[float | None, float | None]  # (earliest, latest); None: not within the horizon
    model_error_K: float  # the band's model-error half-width once the start is forgotten (0: none known)
    measured_C: np.ndarray | None = None
    measured_crossing_s: float | None = None  # where the log's own readings first reach the threshold
    # where the question leaves what the model was identified on (model.experience)
    notes: tuple[str, ...] = ()

    @property
    def horizon_s(self) -> float:
        return float(self.time_s[-1])

    @property
    def covers_measured(self) -> bool | None:
        """Whether the interval holds the measured crossing (``None`` when the log's readings never reach
        it)."""
        if self.measured_crossing_s is None:
            return None
        low, high = self.interval_s
        return (low is not None and low <= self.measured_crossing_s) and (
            high is None or self.measured_crossing_s <= high
        )

    @property
    def measured_error_K(self) -> tuple[float, float] | None:
        """The forecast against the log's own readings over the log: ``(RMSE, largest)`` in K, or ``None``."""
        if self.measured_C is None:
            return None
        error = np.abs(self.predicted_C - self.measured_C)
        error = error[np.isfinite(error)]
        return (float(np.sqrt(np.mean(error**2))), float(error.max())) if error.size else None

    def to_json(self) -> dict:
        error = self.measured_error_K
        return {
            "actuator": self.actuator,
            "threshold_C": self.threshold_C,
            "start_C": self.start_C,
            "level": self.level,
            "horizon_s": self.horizon_s,
            "time_to_threshold_s": self.time_to_threshold_s,
            "interval_s": list(self.interval_s),
            "model_error_K": self.model_error_K,
            "measured_rmse_K": None if error is None else error[0],
            "measured_max_error_K": None if error is None else error[1],
            "measured_crossing_s": self.measured_crossing_s,
            "covers_measured": self.covers_measured,
            "peak_predicted_C": float(np.max(self.predicted_C)),
            "notes": list(self.notes),
        }

    def sentence(self) -> str:
        """The answer in words, with the units and the level."""
        low, high = self.interval_s
        where = f"{self.threshold_C:.1f} degC from {self.start_C:.1f} degC"
        if self.time_to_threshold_s is None:
            head = (f"{self.actuator}: the prediction stays below {where} over {self.horizon_s:.0f} s "
                    f"(peak {np.max(self.predicted_C):.1f} degC)")
            return head + ("" if low is None else f"; at {100 * self.level:.0f} % "
                                                  f"it may reach it from {low:.0f} s")
        upper = "beyond the horizon" if high is None else f"{seconds(high)} s"
        return (f"{self.actuator}: reaches {where} in {seconds(self.time_to_threshold_s)} s "
                f"({100 * self.level:.0f} % interval {seconds(low)} s to {upper})")


def seconds(value: float) -> str:
    """A time in whole seconds, or to a tenth under ten (an interval of 1.6 to 2.4 s is not "2 s to 2 s")."""
    return f"{value:.1f}" if abs(value) < 10 else f"{value:.0f}"


def parameter_draws(
    saved: SavedModel, draws: int, seed: int, spread: str = "jackknife"
) -> list[ThermalModel]:
    """``draws`` models with parameters from the blocked jackknife's covariance (``spread="fit"``: the fit's
    own), seeded, each clipped into its bounds."""
    model = saved.model
    cov = np.asarray(saved.covariance if saved.jackknife is None or spread == "fit" else saved.jackknife,
                     float)
    if draws <= 0 or not np.any(cov):
        return []
    values, vectors = np.linalg.eigh((cov + cov.T) / 2.0)
    root = vectors * np.sqrt(np.clip(values, 0.0, None))
    rng = np.random.default_rng(seed)
    lower = np.array([p.lower for p in model.parameters])
    upper = np.array([p.upper for p in model.parameters])
    lower[0] = max(lower[0], 1e-3)
    out = []
    for z in rng.standard_normal((draws, len(values))):
        out.append(model.with_params(np.clip(model.vector() + root @ z, lower, upper)))
    return out


def forecast(saved: SavedModel, signals: Signals, start_C: float, threshold_C: float, level: float = LEVEL,
             draws: int = DRAWS, seed: int = 0, initial_rate_K_per_s: float = 0.0,
             measured_C: np.ndarray | None = None, history=None) -> Forecast:
    """The forecast of ``saved`` under ``signals`` from ``start_C`` (module docstring for the band).

    ``history``, an :class:`~thermolimb.logs.ActuatorSeries` that ends where the forecast starts (what a
    monitor has seen), places the model's slow states: the model runs over it from its first reading, and the
    difference between its last reading and the model there fades with its slow mass's time constant
    (:attr:`~thermolimb.model.ThermalModel.gap_fade_s`; the winding's in a model without one).
    """
    if not 0.0 < level < 1.0:
        raise ValueError(f"level must lie between 0 and 1, got {level}")
    if not np.isfinite(start_C) or not np.isfinite(threshold_C):
        raise ThermolimbError(f"the start ({start_C}) and the threshold ({threshold_C}) must be finite degC")
    if threshold_C <= start_C:
        raise ThermolimbError(f"{saved.actuator}: the threshold {threshold_C:g} degC is not above the start "
                              f"{start_C:.2f} degC; a time to reach it needs "
                              "a threshold above where the joint starts")
    model = saved.model
    t = signals.time_s - signals.time_s[0]
    ranges = dict(saved.provenance).get("ranges") or {}
    shift = saved.offset_shift_K(signals.ambient_C)  # the offset follows another air

    def run(m: ThermalModel) -> np.ndarray:
        m = shifted(m, shift)
        if history is None:
            return m.simulate(signals, start_C, initial_rate_K_per_s=initial_rate_K_per_s)
        joined = join(history.signals, signals)
        whole = m.simulate(joined, history.temperature_C[0], initial_rate_K_per_s=history.rate_K_per_s())
        ahead = whole[history.n - 1:]
        return ahead + (start_C - ahead[0]) * np.exp(-t / m.gap_fade_s)

    predicted = run(model)
    z = float(ndtri(0.5 + level / 2.0))
    lead = None if saved.residual is None else saved.residual.lead_error_K(level, t)
    spread = PARAMETER_SPREAD if lead is not None else "jackknife"
    parameter_sd = spread_of(run, parameter_draws(saved, draws, seed, spread), predicted)
    model_error = model_error_K(saved, level)
    if lead is None:
        lead = model_error * np.sqrt(1.0 - np.exp(-2.0 * t / model.params["RC_s"]))
    notes, widen = beyond(ranges, signals, start_C, "ambient" in model.columns,
                          saved.channel_units.get("effort", ""), shift)
    hotter, widen_hot = hotter_than_seen(ranges, predicted)
    notes, widen = notes + hotter, np.maximum(widen, widen_hot)
    half = np.sqrt((z * parameter_sd) ** 2 + (lead * widen * extrapolation(saved, predicted, shift)) ** 2)
    if notes:  # an extrapolation is never answered with a zero-width band: at least a tenth of the rise
        half = np.maximum(half, 0.1 * np.abs(predicted - start_C))
    low, high = predicted - half, predicted + half
    if not np.any(saved.covariance) and draws > 0:  # saved without standard errors: said, not hidden
        alone = ("the model's held-out error alone" if saved.residual is not None
                 else "the prediction alone (nor does it hold a held-out residual)")
        notes = notes + [f"the model file holds no standard errors: the interval is {alone}"]
    measured_cross = None if measured_C is None else crossing_s(t, np.asarray(measured_C, float), threshold_C)
    return Forecast(saved.actuator, t, predicted, low, high, float(threshold_C), float(level), float(start_C),
                    crossing_s(t, predicted, threshold_C),
                    (crossing_s(t, high, threshold_C), crossing_s(t, low, threshold_C)), model_error,
                    None if measured_C is None else np.asarray(measured_C, float), measured_cross,
                    tuple(notes))


def spread_of(run, models: list[ThermalModel], predicted: np.ndarray) -> np.ndarray:
    """The standard deviation over ``models``' runs at each sample, accumulated run by run (a 1 kHz hour's 64
    draws would otherwise hold 2 GB at once): deviations from ``predicted`` keep the sums well conditioned."""
    if len(models) < 2:
        return np.zeros_like(predicted)
    total, squares = np.zeros_like(predicted), np.zeros_like(predicted)
    for m in models:
        d = run(m) - predicted
        total += d
        d *= d
        squares += d
    mean = total / len(models)
    return np.sqrt(np.maximum(squares / len(models) - mean * mean, 0.0))


def join(before: Signals, after: Signals) -> Signals:
    """``before`` up to its last sample, then ``after`` from that instant on (its time shifted to follow)."""
    def both(a, b):
        return None if a is None or b is None else np.concatenate([a[:-1], b])

    time = np.concatenate([before.time_s[:-1], after.time_s - after.time_s[0] + before.time_s[-1]])
    missing = [c for c in ("velocity", "current_A", "ambient_C", "housing_C", "power_W")
               if (getattr(before, c) is None) != (getattr(after, c) is None)]
    if missing:
        raise ThermolimbError("the history and the plan must carry the "
                              f"same channels; {missing[0]} is in one only")
    return Signals(time, both(before.effort, after.effort), both(before.velocity, after.velocity),
                   both(before.current_A, after.current_A), both(before.ambient_C, after.ambient_C),
                   both(before.neighbor_temperature_C, after.neighbor_temperature_C), before.neighbor_names,
                   both(before.housing_C, after.housing_C), both(before.power_W, after.power_W),
                   {k: both(v, after.extra[k]) for k, v in before.extra.items() if k in after.extra})


def model_error_K(saved: SavedModel, level: float) -> float:
    """The half-width the model's own error reaches at ``level`` (K): the held-out residual's quantile."""
    return 0.0 if saved.residual is None else saved.residual.abs_quantile_K(level)


def extrapolation(saved: SavedModel, predicted_C: np.ndarray, shift_K: float = 0.0) -> np.ndarray:
    """How far beyond what the held-out data saw a forecast goes: its rise above the model's offset over the
    held-out free run's typical (root-mean-square) rise, at least one: a model's error is mostly an error in
    its gains, which grows with the rise."""
    seen = None if saved.residual is None else saved.residual.rise_K
    if not seen or seen <= 0:
        return np.ones_like(predicted_C)
    rise = np.abs(predicted_C - saved.model.params["T_offset_C"] - shift_K)
    return np.maximum(1.0, rise / seen)


def hold_signals(
    duration_s: float,
    effort: float,
    velocity: float | None = None,
    ambient_C: float | None = None,
    columns: tuple[str, ...] = ("effort",),
    step_s: float | None = None,
) -> Signals:
    """Inputs held constant for ``duration_s``: the plan ``predict --hold`` asks about."""
    if not duration_s > 0 or not np.isfinite(duration_s):
        raise ThermolimbError(f"--duration must be a positive number of seconds, got {duration_s}")
    missing = [c for c in columns if c not in ("effort", "velocity", "ambient")]
    if missing:
        raise ThermolimbError(f"the model reads the log column {missing[0]!r}, "
                              "which a held plan does not give "
                              f"(it gives effort, velocity and ambient); predict over a log instead")
    if "velocity" in columns and velocity is None:
        raise ThermolimbError("the model reads the velocity; give it with the effort: --hold EFFORT,VELOCITY")
    if "ambient" in columns and ambient_C is None:
        raise ThermolimbError("the model reads the ambient temperature; give it with --ambient-C")
    step = step_s or min(1.0, duration_s / 200.0)
    n = int(np.ceil(duration_s / step)) + 1
    time = np.linspace(0.0, duration_s, n)
    full = np.full(n, 1.0)
    return Signals(time, effort * full, None if velocity is None else velocity * full,
                   ambient_C=None if ambient_C is None else ambient_C * full)
