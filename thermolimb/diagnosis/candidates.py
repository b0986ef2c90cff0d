"""Which missing effect explains the residual: quick score tests, then refits.

Quick score (a Lagrange-multiplier test).  Adding effect ``c`` to the fitted
model at its null value (effect absent) changes the free-run simulation, to
first order, by ``S_c dtheta_c`` where ``S_c`` is the sensitivity of the
simulated temperature to ``c``'s parameters -- the effect's signature passed
through the thermal lag.  Part of that signature the current parameters can
already produce (``J``, the Jacobian of the fitted model); what is left,
``S_c_perp = (I - J J^+) S_c``, is what only ``c`` can explain.  The share of
the residual it explains is a partial ``R^2``; ``n_eff R^2`` is the score
statistic, chi-squared with one degree of freedom per parameter, where
``n_eff`` discounts the serial correlation of the residual left once the
candidate has explained its share.

Refit.  Each strong candidate is then fitted for real (output error) and
validated on held-out data like the base model: validation RMSE, fit %,
``delta_bic`` on the training residual, fitted values with uncertainty, a
plausibility check and whether this log identifies it at all.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.stats import chi2

from ..logs import ActuatorSeries
from ..metrics import ar1_variance_factor, information_criteria
from ..model.model import ThermalModel, model_parameters
from ..model.terms import TERMS

SCORE_P_VALUE = 0.01  # candidates below this p-value are refitted
MIN_IMPROVEMENT = 0.10  # a recommendation must cut validation RMSE by at least 10 %
MAX_DELTA_BIC = -10.0  # ... and lower BIC by at least 10 ("very strong" evidence on the training part)


@dataclass
class Candidate:
    """One catalog effect tried on this log."""

    effect: str
    model: tuple[str, ...]
    replaces: str | None = None
    score: float = 0.0
    p_value: float = 1.0
    partial_r2: float = 0.0
    rmse_K: float | None = None
    fit_percent: float | None = None
    improvement: float | None = None
    delta_bic: float | None = None
    params: dict = field(default_factory=dict)
    identifiable: bool | None = None
    plausible: bool | None = None
    implausible_because: str | None = None
    evidence: str = ""
    report: object = field(default=None, repr=False)
    start: dict = field(default_factory=dict, repr=False)  # where the refit starts

    def to_json(self) -> dict:
        out = {
            "effect": self.effect, "rmse_K": self.rmse_K, "fit_percent": self.fit_percent,
            "improvement": self.improvement, "delta_bic": self.delta_bic, "params": self.params,
            "identifiable": self.identifiable, "evidence": self.evidence,
            "score": self.score, "p_value": self.p_value, "plausible": self.plausible,
        }
        if self.replaces:
            out["replaces"] = self.replaces
        return out


def candidate_models(model: tuple[str, ...], series: ActuatorSeries) -> list[Candidate]:
    """Every registered effect not in ``model`` whose columns the log has, plus heat-source swaps."""
    out = []
    for name, term in TERMS.items():
        if name in model or not _has_columns(term, series):
            continue
        out.append(Candidate(name, model + (name,)))
    has_current = series.signals.current_A is not None
    if has_current and "joule" in model and "current_heating" not in model:
        swapped = tuple("current_heating" if t == "joule" else t for t in model)
        out.append(Candidate("current_heating", swapped, replaces="joule"))
    if "current_heating" in model and "joule" not in model:
        swapped = tuple("joule" if t == "current_heating" else t for t in model)
        out.append(Candidate("joule", swapped, replaces="current_heating"))
    return out


def _has_columns(term, series: ActuatorSeries) -> bool:
    for column in term.columns:
        try:
            series.signals.channel(column)
        except KeyError:
            return False
    return True


def simulate_all(model: ThermalModel, series: list[ActuatorSeries]) -> np.ndarray:
    return np.concatenate([model.simulate(s.signals, s.temperature_C[0], initial_rate_K_per_s=s.rate_K_per_s())
                           for s in series])


NUISANCE_GRID = (0.1, 0.3, 1.0, 3.0, 10.0)  # multiples of a nuisance parameter's typical value


def score_candidate(cand: Candidate, base: ThermalModel, train: list[ActuatorSeries], jacobian: np.ndarray,
                    residual: np.ndarray) -> None:
    """Fill ``score``, ``p_value``, ``partial_r2`` and ``start`` of a nested candidate (a swap is not scored).

    Parameters that only mean something once the effect is present
    (``nuisance``, e.g. a second mass's time constant) are scanned over a
    grid and the largest score is kept (a sup-score test).
    """
    term = TERMS[cand.effect] if not cand.replaces else None
    cand.start = dict(base.params)
    if term is None:
        cand.p_value = 0.0  # not nested: always refitted
        cand.start = {k: v for k, v in base.params.items() if k in {p.name for p in model_parameters(cand.model)}}
        return
    nuisance = [p for p in term.parameters if p.nuisance]
    grid = [dict()] if not nuisance else [{p.name: p.typical * g for p in nuisance} for g in NUISANCE_GRID]
    for fixed in grid:
        score, p_value, r2, step = _score_at(cand, term, base, train, jacobian, residual, fixed)
        if score >= cand.score:
            cand.score, cand.p_value, cand.partial_r2 = score, p_value, r2
            cand.start = {**dict(base.params), **step, **fixed}


def _score_at(cand, term, base, train, jacobian, residual, fixed):
    values = dict(base.params)
    values.update({p.name: p.null for p in term.parameters})
    values.update(fixed)
    extended = ThermalModel(cand.model, values)
    at_null = simulate_all(extended, train)
    primary = [p for p in term.parameters if not p.nuisance]
    columns = []
    for p in primary:
        step = 0.05 * abs(p.typical) if p.typical else 1e-3
        step = step if p.null + step <= p.upper else -step
        moved = extended.with_params({**extended.params, p.name: p.null + step})
        columns.append((simulate_all(moved, train) - at_null) / step)
    S = np.column_stack(columns)
    coef, *_ = np.linalg.lstsq(jacobian, S, rcond=None)
    S_perp = S - jacobian @ coef
    null_step = {p.name: p.null for p in primary}
    if not np.any(np.abs(S_perp) > 0) or residual @ residual == 0:
        return 0.0, 1.0, 0.0, null_step
    beta, *_ = np.linalg.lstsq(S_perp, residual, rcond=None)
    explained = S_perp @ beta
    r2 = float(explained @ explained / (residual @ residual))
    # serial correlation of what is left once the candidate explains its share: under the
    # alternative the left-over is the noise whose correlation discounts the sample count
    n_eff = residual.size / ar1_variance_factor(residual - explained)
    score = n_eff * r2
    # a Gauss-Newton step from the null, clipped into the bounds, starts the refit
    step = {p.name: float(np.clip(p.null + b, p.lower, p.upper)) for p, b in zip(primary, beta)}
    return score, float(chi2.sf(score, S.shape[1])), r2, step


def bic(residual: np.ndarray, n_params: int) -> float:
    """BIC on the training residual; it overstates evidence for correlated residuals, which is why a
    recommendation also needs a held-out improvement."""
    return information_criteria(residual, n_params)["bic"]


def judge(cand: Candidate, report, base_rmse: float, base_bic: float, train_residual: np.ndarray) -> None:
    """Fill the refit results of a candidate from its :class:`~thermolimb.evaluation.FitReport`."""
    cand.report = report
    cand.rmse_K = report.validation["rmse_K"]
    cand.fit_percent = report.validation["fit_percent"]
    cand.improvement = 1.0 - cand.rmse_K / base_rmse if base_rmse > 0 else 0.0
    cand.delta_bic = bic(train_residual, len(report.model.params)) - base_bic
    term = TERMS[cand.effect]
    identifiable = True
    cand.implausible_because = term().implausible(report.model.params)
    for p in term.parameters:
        value, se = report.model.params[p.name], report.stderr[p.name]
        cand.params[p.name] = {"value": value, "stderr": float(se), "unit": p.unit}
        span = p.upper - p.lower if np.isfinite(p.upper - p.lower) else max(abs(value), 1.0)
        at_bound = min(abs(value - p.lower), abs(p.upper - value)) < 1e-6 * span
        if not np.isfinite(se) or (not p.nuisance and (abs(value) < 2 * se)) or (at_bound and not p.nuisance):
            identifiable = False
    cand.identifiable = identifiable
    cand.plausible = cand.implausible_because is None
