"""Fit on the first part of a log, validate by free-run simulation on the rest.

This is the rule every command uses (``fit``, later ``compare`` and
``diagnose``): the model is identified on the first ``split`` of each log's
time span, then simulated over the remainder from the measured temperature at
the split, from the inputs alone, with no temperature updates.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Sequence

import numpy as np

from .identification import ESTIMATORS, ThermalEstimator
from .logs import MIN_SAMPLES, ActuatorSeries, LogError
from .metrics import fit_metrics
from .model.model import ThermalModel


@dataclass(frozen=True)
class Segment:
    """One stretch of measured and simulated temperature."""

    time_s: np.ndarray
    measured_C: np.ndarray
    simulated_C: np.ndarray
    effort: np.ndarray


@dataclass(frozen=True)
class FitReport:
    """The outcome of fitting and validating one actuator."""

    actuator: str
    method: str
    model: ThermalModel
    stderr: dict
    train: dict
    validation: dict
    train_segments: tuple[Segment, ...] = field(repr=False, default=())
    validation_segments: tuple[Segment, ...] = field(repr=False, default=())

    def to_json(self) -> dict:
        """The record ``thermolimb fit --json`` prints."""
        units = {p.name: p.unit for p in self.model.parameters}
        return {
            "actuator": self.actuator,
            "model": list(self.model.terms),
            "method": self.method,
            "params": {
                name: {"value": value, "stderr": float(self.stderr[name]), "unit": units[name]}
                for name, value in self.model.params.items()
            },
            "train": self.train,
            "validation": self.validation,
        }


def _segment(model: ThermalModel, series: ActuatorSeries, rate_K_per_s: float) -> Segment:
    sim = model.simulate(series.signals, series.temperature_C[0], initial_rate_K_per_s=rate_K_per_s)
    return Segment(series.time_s, series.temperature_C, sim, series.signals.effort)


def _metrics(segments: Sequence[Segment]) -> dict:
    return fit_metrics(np.concatenate([s.measured_C for s in segments]),
                       np.concatenate([s.simulated_C for s in segments]))


def make_estimator(method: str, model: str | Sequence[str]) -> ThermalEstimator:
    if method not in ESTIMATORS:
        raise ValueError(f"unknown method {method!r}; expected one of {', '.join(ESTIMATORS)}")
    return ESTIMATORS[method](model=model)


def fit_and_validate(
    series: Sequence[ActuatorSeries],
    model: str | Sequence[str],
    split: float = 0.7,
    method: str = "output_error",
    estimator: ThermalEstimator | None = None,
) -> FitReport:
    """Fit jointly on the first ``split`` of every series (one actuator, one or several logs), validate on the rest."""
    parts = [s.split(split) for s in series]
    train = [p[0] for p in parts]
    valid = [p[1] for p in parts]
    est = (estimator or make_estimator(method, model)).fit(train)
    train_segments = tuple(_segment(est.model_, s, s.rate_K_per_s()) for s in train)
    # the trend at the split comes from the training data before it
    valid_segments = tuple(_segment(est.model_, v, t.rate_K_per_s(at_end=True)) for t, v in zip(train, valid))
    return _report(series[0].actuator, est, train_segments, valid_segments)


def _report(actuator: str, est: ThermalEstimator, train_segments, valid_segments) -> FitReport:
    return FitReport(actuator=actuator, method=est.method, model=est.model_, stderr=est.stderr_,
                     train=_metrics(train_segments), validation=_metrics(valid_segments),
                     train_segments=tuple(train_segments), validation_segments=tuple(valid_segments))


def cross_validate(
    series: Sequence[ActuatorSeries],
    model: str | Sequence[str],
    folds: int,
    method: str = "output_error",
    make: "callable | None" = None,
) -> FitReport:
    """Blocked cross-validation: ``folds`` contiguous blocks of each series.

    Each block is validated by free-run simulation from its measured start,
    with a model fitted jointly on the pieces before and after it.  The
    report's parameters come from a fit on everything; its ``validation``
    pools the errors of every block.  ``make()`` returns a fresh estimator
    (default: ``method``'s).
    """
    if folds < 2:
        raise ValueError(f"--cv needs at least 2 folds, got {folds}")
    make = make or (lambda: make_estimator(method, model))
    segments, train_segments = [], []
    for s in series:
        edges = np.linspace(0, s.n, folds + 1).astype(int)
        if np.min(np.diff(edges)) < MIN_SAMPLES:
            raise LogError(f"actuator {s.actuator}: {s.n} samples are too few for {folds} folds "
                           f"(each needs at least {MIN_SAMPLES})")
        for lo, hi in zip(edges[:-1], edges[1:]):
            pieces = [p for p in (s.slice(0, lo), s.slice(hi, s.n)) if p.n >= MIN_SAMPLES]
            pieces += [o for o in series if o is not s]
            est = make().fit(pieces)
            block = s.slice(lo, hi)
            # the trend at the block's start comes from the data before it (the first block: its own start)
            rate = s.slice(0, lo + 1).rate_K_per_s(at_end=True) if lo > 0 else block.rate_K_per_s()
            segments.append(_segment(est.model_, block, rate))
    full = make().fit(list(series))
    train_segments = tuple(_segment(full.model_, s, s.rate_K_per_s()) for s in series)
    return _report(series[0].actuator, full, train_segments, segments)
