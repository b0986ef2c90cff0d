"""A fitted model as a model file's entry: :func:`saved_from_report` turns a fit's
:class:`~thermolimb.workbench.validation.FitReport` into a :class:`~thermolimb.model.saved.SavedModel`, with
the held-out residual's statistics and the blocked jackknife's covariance a forecast's interval needs."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import Sequence

import numpy as np

from ..model.generated import specs_of
from ..model.residual_stats import RESIDUAL_QUANTILES, ResidualStats
from ..model.saved import (
    JACKKNIFE_BLOCKS,
    MIN_JACKKNIFE_FITS,
    SavedModel,
    provenance,
)
from ..util.errors import ThermolimbError
from .validation import make_estimator


def saved_from_report(report, paths: Sequence[str | Path], limit_C: float | None = None) -> SavedModel:
    """A :class:`SavedModel` from a fit's :class:`~thermolimb.workbench.validation.FitReport`."""
    model = report.model
    names = [p.name for p in model.parameters]
    covariance = getattr(report.estimator, "covariance_", None)
    if covariance is None or np.shape(covariance) != (len(names), len(names)):
        covariance = np.diag([float(report.stderr[n]) ** 2 for n in names])
    segments = report.validation_segments or report.train_segments
    residual = np.concatenate([s.measured_C - s.simulated_C for s in segments])
    span = float(sum(s.time_s[-1] - s.time_s[0] for s in segments if s.time_s.size))
    rise = np.concatenate([s.simulated_C for s in segments]) - model.params["T_offset_C"]
    rise = float(np.sqrt(np.mean(rise * rise)))
    stats = replace(ResidualStats.of(residual, span, rise), **lead_profile(report))
    return SavedModel(report.actuator, model, {n: float(report.stderr[n]) for n in names},
                      np.asarray(covariance, float), jackknife_covariance(report),
                      {p.name: report.unit(p) for p in model.parameters}, dict(report.channel_units),
                      dict(report.validation), stats, provenance(paths, report.train_series), limit_C,
                      report.method, report.scheme, specs_of(model.terms))


LEADS_S = (10.0, 30.0, 60.0, 120.0, 300.0, 600.0, 900.0, 1800.0, 3600.0, 7200.0)
LEAD_STARTS = 400  # start points per lead, spread over the runs


def lead_profile(report) -> dict:
    """How far a forecast started from a reading drifts from the readings after each lead: over every run the
    model was fitted on, from start points spread over it, the error a forecast makes -- the free run's
    residual after the lead, less the residual at the start faded as the forecast fades it (``gap_fade_s``),
    as :func:`thermolimb.forecast.forecast` corrects a forecast to its start -- and its quantiles per lead.
    The runs include the data fitted on, so each quantile is scaled by the held-out error over the training
    error (never below one).  Leads longer than half the longest run are not measured."""
    model, fade = report.model, report.model.gap_fade_s
    offsets = getattr(report.estimator, "offsets_", None) or [None] * len(report.train_series)
    runs = []
    for s, offset in zip(report.train_series, offsets):
        whole = replace(s, fit_mask=None)
        runs.append((whole.time_s, whole.temperature_C - model.free_run(whole, offsets=offset)))
    longest = max((t[-1] - t[0] for t, _ in runs), default=0.0)
    leads = [h for h in LEADS_S if h <= 0.5 * longest]
    if not leads:
        return {}
    scale = max(1.0, report.validation["rmse_K"] / max(report.train["rmse_K"], 1e-12))
    table = []
    for lead in leads:
        errors = []
        for t, r in runs:
            usable = np.flatnonzero(t <= t[-1] - lead)
            starts = usable[:: max(1, usable.size // LEAD_STARTS)] if usable.size else usable
            ends = np.searchsorted(t, t[starts] + lead)
            errors.append(np.abs(r[ends] - r[starts] * np.exp(-(t[ends] - t[starts]) / fade)))
        errors = np.concatenate(errors)
        table.append(
            scale * np.quantile(errors, RESIDUAL_QUANTILES)
            if errors.size
            else np.zeros(len(RESIDUAL_QUANTILES))
        )
    table = np.array(table)
    return {
        "leads_s": tuple(leads),
        "lead_quantiles_K": {
            f"{q:g}": tuple(map(float, table[:, k])) for k, q in enumerate(RESIDUAL_QUANTILES)
        },
    }


def jackknife_covariance(report) -> np.ndarray | None:
    """The delete-one-block jackknife covariance of the parameters (Künsch's blocked jackknife for dependent
    data): each run cut into :data:`JACKKNIFE_BLOCKS` blocks in time, the model refitted without each block in
    turn, ``(K - 1)/K * sum (theta_k - mean)(theta_k - mean)^T``.

    Where the model misses physics, the fit's covariance (from the curvature at its optimum, for a model taken
    as true) is far too narrow: the parameters compensate for what is missing differently on each part of a
    log.  The refits see that; on the plant logs of ``benchmarks/forecast.py`` their spread is 4-10 times the
    fit's standard errors.  ``None`` when fewer than :data:`MIN_JACKKNIFE_FITS` refits succeed.
    """
    series = list(report.train_series)
    if not series:
        return None
    thetas = []
    for k in range(JACKKNIFE_BLOCKS):
        parts = []
        for run in series:
            lo, hi = k * run.n // JACKKNIFE_BLOCKS, (k + 1) * run.n // JACKKNIFE_BLOCKS
            parts += [p for p in (run.slice(0, lo), run.slice(hi, run.n)) if p.n >= 20]
        try:
            estimator = make_estimator(report.method, report.model.terms).fit(parts)
        except (ThermolimbError, ValueError, np.linalg.LinAlgError):
            continue
        thetas.append(estimator.model_.vector())
    if len(thetas) < MIN_JACKKNIFE_FITS:
        return None
    theta = np.array(thetas)
    centred = theta - theta.mean(axis=0)
    return (len(thetas) - 1) / len(thetas) * centred.T @ centred
