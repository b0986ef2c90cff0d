"""A fitted model as a model file's entry: :func:`saved_from_report` turns a fit's
:class:`~thermolimb.workbench.validation.FitReport` into a :class:`~thermolimb.model.saved.SavedModel`, with the
held-out residual's statistics and the blocked jackknife's covariance a forecast's interval needs."""

from __future__ import annotations

from pathlib import Path
from typing import Sequence

import numpy as np

from ..model.saved import JACKKNIFE_BLOCKS, MIN_JACKKNIFE_FITS, ResidualStats, SavedModel, provenance
from ..model.terms import TERMS
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
    sources = {t: TERMS[t].source for t in model.terms if getattr(TERMS[t], "generated", False)}
    return SavedModel(report.actuator, model, {n: float(report.stderr[n]) for n in names},
                      np.asarray(covariance, float), jackknife_covariance(report), {p.name: report.unit(p) for p in model.parameters},
                      dict(report.channel_units), dict(report.validation), ResidualStats.of(residual, span, rise),
                      provenance(paths, report.train_series), limit_C, report.method, report.scheme, sources)



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
