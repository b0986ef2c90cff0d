"""Diagnose a model against a log: residual analysis, ranked candidate effects, a recommendation.

``diagnose(series, model)`` fits the model (output error, the ``fit`` split
rule), analyses its residual, scores every catalog effect the model lacks,
refits the strong ones and recommends the effect to add, or none.
``auto_diagnose`` adds recommended effects one at a time until none helps.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Sequence

import numpy as np

from ..evaluation import FitReport, cross_validate, fit_and_validate
from ..identification import IdentifiabilityError, OutputError
from ..logs import ActuatorSeries
from ..model.terms import parse_model
from ..progress import progress
from .candidates import (MAX_DELTA_BIC, MIN_IMPROVEMENT, SCORE_P_VALUE, Candidate, bic, candidate_models, judge,
                         score_candidate, simulate_all)
from .evidence import describe

ALWAYS_REFIT = 3
from .residuals import ResidualAnalysis, analyse_residuals


@dataclass
class Diagnosis:
    actuator: str
    model: tuple[str, ...]
    base: FitReport
    base_bic: float
    residuals: ResidualAnalysis
    candidates: list[Candidate]
    recommended: Candidate | None
    auto: list[dict] | None = field(default=None)

    def to_json(self) -> dict:
        out = {
            "actuator": self.actuator,
            "model": list(self.model),
            "base": {**self.base.validation, "bic": self.base_bic},
            "candidates": [c.to_json() for c in self.candidates],
            "recommended": None if self.recommended is None else self.recommended.effect,
            "recommended_model": None if self.recommended is None else list(self.recommended.model),
            "residuals": self.residuals.to_json(),
        }
        if self.auto is not None:
            out["auto"] = self.auto
        return out


REFIT_EVALUATIONS = 12  # simulations per parameter for a candidate's refit; good fits need fewer than 10


def _fit(series: Sequence[ActuatorSeries], model, split: float, initial=None,
         cv: int | None = None) -> tuple[FitReport, OutputError]:
    """Fit and validate: single split, or blocked cross-validation over ``cv`` folds."""

    def make():
        return OutputError(model=model, initial=initial or None, max_nfev=REFIT_EVALUATIONS)

    if cv:
        return cross_validate(series, model, cv, make=make), make().fit(list(series))
    est = make()
    return fit_and_validate(series, model, split=split, estimator=est), est


def diagnose(series: Sequence[ActuatorSeries], model="joule,effort_bias", split: float = 0.7,
             refit: str = "strong", quiet: bool = True, cv: int | None = None) -> Diagnosis:
    """Fit ``model``, analyse its residual, rank the missing effects.

    Held-out errors come from the ``split`` rule, or with ``cv=K`` from
    blocked cross-validation over K contiguous folds (the score tests then
    use a fit on the whole log).  ``refit="strong"`` refits candidates whose score test has p < 0.01 and
    the three that explain most of the residual; ``"all"`` refits every candidate.
    """
    model = parse_model(model)
    series = list(series)
    base, est = _fit(series, model, split, cv=cv)
    train = list(series) if cv else [s.split(split)[0] for s in series]
    measured = np.concatenate([s.temperature_C for s in train])
    base_sim = simulate_all(base.model, train)
    residual = measured - base_sim
    jacobian = est.optimizer_result_.jac  # d simulated / d parameters on the training data
    base_bic = bic(residual, len(base.model.params))
    analysis = analyse_residuals(train[0], base_sim[: train[0].n])

    candidates = candidate_models(model, series[0])
    for cand in candidates:
        score_candidate(cand, base.model, train, jacobian, residual)
    # strong: significant by the score test, or among the best scores (the test is only a first
    # look, weak where a nuisance parameter hides the effect); validation decides
    top = set(id(c) for c in sorted(candidates, key=lambda c: -c.partial_r2)[:ALWAYS_REFIT])
    to_refit = [c for c in candidates if refit == "all" or c.p_value < SCORE_P_VALUE or id(c) in top]
    for cand in progress(to_refit, desc="refits", disable=quiet):
        try:
            # two starts, the score test's one step and least squares with typical values; the better fit wins
            fits = [_fit(series, cand.model, split, initial=cand.start, cv=cv)[0],
                    _fit(series, cand.model, split, cv=cv)[0]]
            report = min(fits, key=lambda r: r.train["rmse_K"])
        except IdentifiabilityError as exc:
            cand.identifiable = False
            cand.evidence = f"not identifiable from this log: {exc}"
            continue
        cand_train_residual = measured - simulate_all(report.model, train)
        judge(cand, report, base.validation["rmse_K"], base_bic, cand_train_residual)
    for cand in candidates:
        if not cand.evidence:
            cand.evidence = describe(cand, analysis, base.validation["rmse_K"])
    candidates.sort(key=_rank)
    recommended = next((c for c in candidates if _helps(c)), None)
    return Diagnosis(series[0].actuator, model, base, base_bic, analysis, candidates, recommended)


def _rank(c: Candidate):
    """Plausible refitted candidates by validation RMSE, then implausible ones, then the rest by score.

    An unidentifiable candidate yields to an identifiable one within 1 % of its error.
    """
    if c.rmse_K is None:
        return (2, 0.0, -c.score)
    return (0 if c.plausible else 1, c.rmse_K * (1.0 if c.identifiable else 1.01), 0.0)


def _helps(c: Candidate) -> bool:
    return (c.improvement is not None and c.improvement >= MIN_IMPROVEMENT
            and c.delta_bic is not None and c.delta_bic <= MAX_DELTA_BIC)


def auto_diagnose(series: Sequence[ActuatorSeries], model="joule,effort_bias", split: float = 0.7,
                  max_steps: int = 5, quiet: bool = True, cv: int | None = None) -> tuple[Diagnosis, list[Diagnosis]]:
    """Add the recommended effect while one helps; returns the first diagnosis and every step's."""
    steps = [diagnose(series, model, split, quiet=quiet, cv=cv)]
    while steps[-1].recommended is not None and len(steps) <= max_steps:
        steps.append(diagnose(series, steps[-1].recommended.model, split, quiet=quiet, cv=cv))
    waterfall = [{"model": list(d.model), "rmse_K": d.base.validation["rmse_K"],
                  "fit_percent": d.base.validation["fit_percent"]} for d in steps]
    first = steps[0]
    first.auto = waterfall
    return first, steps
