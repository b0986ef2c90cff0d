"""Changes to the model worth trying on a log: add an effect, drop a term, swap a heat source.

Quick score (a Lagrange-multiplier test) for an added effect.  Adding effect
``c`` to the fitted model at its null value (effect absent) changes the
free-run simulation, to first order, by ``S_c dtheta_c`` where ``S_c`` is the
sensitivity of the simulated temperature to ``c``'s parameters -- the effect's
signature passed through the thermal lag.  Part of that signature the current
parameters can already produce (``J``, the Jacobian of the fitted model); what
is left, ``S_c_perp = (I - J J^+) S_c``, is what only ``c`` can explain.  The
share of the residual it explains is a partial ``R^2``; ``n_eff R^2`` is the
score statistic, chi-squared with one degree of freedom per parameter, where
``n_eff`` discounts the serial correlation of the residual left once the
candidate has explained its share.  When nothing is left (``S_c_perp ~ 0``)
the effect is *confounded* on this log with what the model already has (speed
losses at constant speed look like an offset) and is named so, not refitted.

Time scales.  An effect's time constants (a second mass, a sensor lag) are scanned over the time scales the
log can show, a few samples to half its length; the score keeps the best, the refit starts from the best few.
Refit.  Each candidate worth it is then fitted for real (output error) and validated on held-out data like the
base model: validation RMSE, improvement, ``delta_bic`` on the training residual, fitted values with
uncertainty, plausibility, identifiability and, when the refit fails, why.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Mapping

import numpy as np

from ...identification.metrics import (
    ar1_variance_factor,
    chi2_sf,
    information_criteria,
)
from ...identification.thinning import fit_rows
from ...logs import ActuatorSeries
from ...model.guard import instance
from ...model.model import ThermalModel, model_parameters
from ...model.terms import TERMS
from ...util.frozen import FrozenMapping

SCORE_P_VALUE = 0.01  # candidates below this p-value are refitted
MIN_IMPROVEMENT = 0.10  # an added effect must cut validation RMSE by at least 10 %
# a term goes when held-out data rejects it by this much, whatever the training fit says (it extrapolates
# badly)
DROP_IMPROVEMENT = 0.05
MAX_DELTA_BIC = -10.0  # ... and lower BIC by at least 10 ("very strong" evidence on the training part)
CONFOUNDED_FRACTION = 1e-3  # a signature with less than this share of its own is confounded
COLLINEAR = 0.999  # heat sources whose regressors correlate at least this much cannot be told apart
TIME_SCALES = 5  # time scales a log can show, where non-nuisance times (a sensor lag) start their refits
SCAN_POINTS = 7  # values of a nuisance parameter the score scans (and the refit's profile holds)
SCAN_SPAN = 2.0  # the longest time scanned, in log lengths: a mass slower than the log still bends its curve
REFIT_STARTS = 2  # refits of a time-scale effect, from its best-scoring time scales


@dataclass(frozen=True)
class Candidate:
    """One change to the model tried on this log: ``kind`` ``"add"`` (the catalog's ``effect`` joins the
    model, with the terms it ``brings``), ``"channel"`` (a form of the extra channel ``channel``, with the
    masses it ``brings``), ``"discovered"`` (a form found by :mod:`.discovery`), ``"drop"`` (``effect``
    leaves) or ``"swap"`` (``effect`` replaces ``replaces``).

    Immutable: each stage returns a new record with its findings filled in -- the screen
    (:func:`score_candidate`: ``score``, ``p_value``, ``starts``, ``confounded``; :func:`.screen.unexcited`),
    the refit and judgement (:func:`.judgement.judge`: ``report``, ``rmse_K``, ``improvement`` ...), the
    stability check (:func:`.stability.check`: ``selection_frequency``, ``stability_sentence``,
    ``unstable_because``) and the walk's end (:func:`.reversed_split.walk_cut`: ``refuted_because``)."""

    effect: str
    model: tuple[str, ...]
    kind: str = "add"
    replaces: str | None = None
    also_drops: tuple[str, ...] = ()  # a swap that also removes the terms built on the old heat source
    score: float = 0.0
    p_value: float = 1.0
    partial_r2: float = 0.0
    rmse_K: float | None = None
    fit_percent: float | None = None
    improvement: float | None = None
    delta_bic: float | None = None
    params: Mapping = field(default_factory=FrozenMapping)
    identifiable: bool | None = None
    plausible: bool | None = None
    implausible_because: str | None = None
    confounded: str | None = None
    failure: str | None = None
    flags: tuple[str, ...] = ()
    evidence: str = ""
    report: object = field(default=None, repr=False)
    starts: tuple[dict, ...] = field(default=(), repr=False)  # where refits start
    scan: tuple[tuple[dict, dict], ...] = field(default=(), repr=False)  # (nuisance values, start there)
    channel: str | None = None  # the extra channel a "channel" candidate reads
    # terms it needs that the model lacks, added with it (a mass its channel acts on)
    brings: tuple[str, ...] = ()
    channel_unit: str | None = None
    formula: str | None = None  # a generated term's heat in symbols
    source: str | None = field(default=None, repr=False)  # a generated term's Python source (--propose)
    skipped: str | None = None  # why a candidate worth a refit was not refitted
    broken: str | None = None  # a user's term that broke its contract while being tried: set aside, and why
    selection_frequency: float | None = None  # share of the stability replicates that take it (when checked)
    # how the replicates that took its effect took it, by label
    selected_as: Mapping = field(default_factory=FrozenMapping)
    # a replicate's: whether the whole log's refit of this change was plausible
    settled_plausible: bool | None = None
    stability_sentence: str | None = None  # how often it was taken, and what the replicates varied
    unstable_because: str | None = None  # it helps, but the replicates do not take it often enough
    refuted_because: str | None = None  # it helps, but the run's part it was not judged on refutes it
    # why not judged: the channel it rides on barely moves, or the effort cannot pin it
    unexcited: str | None = None
    units: tuple[int, int] | None = None  # held-out units (runs, blocks) it lowers the error on, of how many
    unit_word: str = "parts"
    robust_improvement: float | None = None  # the held-out gain without its most influential samples
    fragile: str | None = None  # the gain rests on a few held-out samples: why
    @property
    def adds(self) -> bool:  # an added effect: from the catalog, a channel, or a discovered form
        return self.kind in ("add", "channel", "discovered")

    @property
    # the term its score test and profile search: a mass it brings (its channel's form has no
    def searched(self):
        # gradient at the mass's null), else its own
        return TERMS[self.brings[0] if self.brings else self.effect]

    @property
    def label(self) -> str:
        if self.kind == "channel":
            # "1": a plain number
            unit = "" if self.channel_unit in (None, "", "1") else f", in {self.channel_unit}"
            brought = "".join(f"{b} with " for b in self.brings)
            return f"+ {brought}{self.effect} (from the channel {self.channel}{unit})"
        if self.kind == "discovered":
            return f"+ {self.effect} (discovered)"
        if self.kind == "drop":
            return f"- {self.effect}"
        if self.kind == "swap":
            return f"{self.effect} for {','.join((self.replaces,) + self.also_drops)}"
        return f"+ {''.join(f'{b} with ' for b in self.brings)}{self.effect}"

    @property
    def not_refitted_because(self) -> str:
        """Why a candidate has no refit: confounded, failed, outdone by a stronger form, or its score test."""
        return (self.broken or self.unexcited or self.confounded or self.failure or self.skipped
                or f"score test p = {self.p_value:.2g}")

    @property
    def held_back_because(self) -> str | None:
        """Why a change that helps is not taken: refuted by the run's other part, or unstable over
        replicates."""
        return self.refuted_because or self.unstable_because

    @property
    def refitted(self) -> bool:
        return self.rmse_K is not None

    @property
    def helps(self) -> bool:
        """Held-out error and the information criterion both favour the change (see :func:`judge`); a change
        that brings physics in must also lower the error on most held-out runs (or blocks), and keep its gain
        without the few held-out samples most in its favour."""
        if not self.refitted:
            return False
        if self.kind == "drop":
            # a term that extrapolates badly, or one the data does not need: simpler and no worse
            return self.improvement >= DROP_IMPROVEMENT or (self.improvement >= 0.0 and self.delta_bic < 0.0)
        most = self.units is None or 2 * self.units[0] > self.units[1]
        return (self.improvement >= MIN_IMPROVEMENT and self.delta_bic <= MAX_DELTA_BIC and most
                and self.fragile is None)

    @property
    def eligible(self) -> bool:
        """It helps, and is physically plausible, identifiable, not confounded, and its refit did not fail."""
        return (self.helps and self.confounded is None and self.failure is None and self.broken is None
                and self.unexcited is None and self.plausible is not False and self.identifiable is not False)

    @property
    def status(self) -> str:
        """One word for tables and plots."""
        if self.broken:
            return "set aside"
        if self.unexcited:
            return "not judged"
        if self.confounded:
            return "confounded"
        if not self.refitted:
            return "not refitted" if self.failure is None else "refit failed"
        if self.failure:
            return "refit failed"
        if self.plausible is False:
            return "implausible"
        if self.identifiable is False:
            return "unidentifiable"
        if self.refuted_because:
            return "refuted"
        if self.unstable_because:
            return "unstable"
        return "helps" if self.helps else "does not help"

    def spec(self) -> dict:
        """What a stability replicate needs to rebuild this change (:meth:`from_spec`), its fitted values
        included (the replicate's refits start from them)."""
        fitted = dict(self.report.model.params) if self.report is not None else {}
        return {"effect": self.effect, "model": self.model, "kind": self.kind, "replaces": self.replaces,
                "also_drops": self.also_drops, "channel": self.channel, "channel_unit": self.channel_unit,
                "formula": self.formula, "fitted": fitted, "plausible": self.plausible, "brings": self.brings}

    @classmethod
    def from_spec(cls, spec: dict) -> "Candidate":
        return cls(spec["effect"], tuple(spec["model"]), kind=spec["kind"], replaces=spec["replaces"],
                   also_drops=tuple(spec["also_drops"]), channel=spec["channel"],
                   channel_unit=spec["channel_unit"], formula=spec["formula"],
                   settled_plausible=spec.get("plausible"), brings=tuple(spec["brings"]))

    def to_json(self) -> dict:
        out = {
            "effect": self.effect, "kind": self.kind, "label": self.label, "rmse_K": self.rmse_K,
            "fit_percent": self.fit_percent, "improvement": self.improvement, "delta_bic": self.delta_bic,
            "params": dict(self.params), "identifiable": self.identifiable, "plausible": self.plausible,
            "implausible_because": self.implausible_because, "confounded": self.confounded,
            "failure": self.failure, "flags": list(self.flags), "status": self.status,
            "eligible": self.eligible,
            "evidence": self.evidence, "score": self.score, "p_value": self.p_value,
            "selection_frequency": self.selection_frequency,
            "not_judged": self.unexcited, "helps_on_units": None if self.units is None else list(self.units),
            "improvement_without_influential": self.robust_improvement, "fragile": self.fragile,
            # every value of the refitted model (the term's own are in params), which its sentences may name
            "model_params": None if self.report is None else dict(self.report.model.params),
        }
        if self.skipped:
            out["skipped"] = self.skipped
        if self.broken:
            out["set_aside"] = self.broken
        if self.refuted_because:
            out["refuted"] = self.refuted_because
        if self.replaces:
            out["replaces"] = self.replaces
            out["also_drops"] = list(self.also_drops)
        if self.channel is not None:
            out["channel"] = {"name": self.channel, "unit": self.channel_unit}
        if self.formula is not None:
            out["formula"] = self.formula
        return out


def _has_columns(term, series: ActuatorSeries) -> bool:
    return all(series.signals.has(c) for c in term.columns)


def candidate_models(model: tuple[str, ...], series: ActuatorSeries) -> list[Candidate]:
    """Every registered effect not in ``model`` that the log can feed, every term that can go, every
    heat-source swap."""
    out = []
    for name, term in TERMS.items():
        # a third mass brings the second: two at once
        brings = tuple(r for r in term.requires if r not in model)
        if (name not in model and not term.generated and _has_columns(term, series) and (term.carries_state
                or not brings) and all(q in model for b in brings for q in TERMS[b].requires)):
            out.append(Candidate(name, model + brings + (name,), brings=brings))
    sources = [n for n in model if TERMS[n].is_heat_source]
    for name in model:
        rest = tuple(t for t in model if t != name)
        needed = any(name in TERMS[t].requires for t in rest)
        if any(TERMS[t].is_heat_source for t in rest) and not needed:
            out.append(Candidate(name, rest, kind="drop"))
    for old in sources:
        for new, term in TERMS.items():
            if term.is_heat_source and not term.generated and new not in model and _has_columns(term, series):
                swapped = tuple(new if t == old else t for t in model)
                out.append(Candidate(new, swapped, kind="swap", replaces=old))
                # the simplest form: also without the terms that only read effort, which the old source used
                extra = tuple(t for t in model if t not in sources and "effort" in TERMS[t].columns
                              and "effort" not in term.columns)
                if extra:
                    out.append(Candidate(new, tuple(t for t in swapped if t not in extra), kind="swap",
                                         replaces=old, also_drops=extra))
    return out


def simulate_all(model: ThermalModel, series: list[ActuatorSeries], stride: int = 1) -> np.ndarray:
    """The free runs of the series, every ``stride``-th sample of each, concatenated."""
    return np.concatenate([model.free_run(s)[fit_rows(s, stride)] for s in series])


def time_scales_s(series: list[ActuatorSeries]) -> np.ndarray:
    """Time constants a log can show: from three sampling intervals to half its length, log-spaced."""
    dt = min(s.median_dt_s for s in series)
    duration = max(s.duration_s for s in series)
    lo, hi = 3.0 * dt, max(0.5 * duration, 6.0 * dt)
    return np.geomspace(lo, hi, TIME_SCALES)


def scan_values(p, series: list[ActuatorSeries]) -> np.ndarray:
    """Values of a nuisance parameter to scan: for a time, from three sampling intervals to ``SCAN_SPAN`` log
    lengths, log-spaced; otherwise a tenth to ten times its typical size."""
    if p.unit == "s":
        lo = 3.0 * min(s.median_dt_s for s in series)
        hi = max(SCAN_SPAN * max(s.duration_s for s in series), 2.0 * lo)
        values = np.geomspace(lo, hi, SCAN_POINTS)
    else:
        values = p.typical * np.geomspace(0.1, 10.0, SCAN_POINTS)
    return np.clip(values, p.lower, p.upper)


def _grid(term, series) -> list[dict]:
    """Points of the term's nuisance parameters to scan (:func:`scan_values`, stepped together)."""
    nuisance = [p for p in term.parameters if p.nuisance]
    if not nuisance:
        return [{}]
    values = {p.name: scan_values(p, series) for p in nuisance}
    return [{name: float(v[k]) for name, v in values.items()} for k in range(SCAN_POINTS)]


def confounded_swap(cand: Candidate, series: list[ActuatorSeries]) -> str | None:
    """Why a swapped heat source cannot be told from the one it replaces on this log, or ``None``."""
    a, b = instance(cand.replaces), instance(cand.effect)
    fa, fb = ([t.features(s.signals, s.temperature_C) for s in series] for t in (a, b))
    # a form not linear in its parameters (a conductance): the refits judge
    if any(f is None for f in fa + fb):
        return None
    xa, xb = np.concatenate([np.ravel(f) for f in fa]), np.concatenate([np.ravel(f) for f in fb])
    if np.ptp(xa) == 0 or np.ptp(xb) == 0:
        return None
    r = float(np.corrcoef(xa, xb)[0, 1])
    if abs(r) >= COLLINEAR:
        return (f"{cand.effect} and {cand.replaces} move together "
                f"on this log (correlation {r:.4f}): it cannot tell "
                f"them apart; a log in which their inputs vary apart (e.g. current without torque) can")
    return None


def score_candidate(cand: Candidate, base: ThermalModel, train: list[ActuatorSeries], jacobian: np.ndarray,
                    residual: np.ndarray, stride: int = 1, base_run: np.ndarray | None = None) -> Candidate:
    """The screen's record of a change: ``cand`` with its ``score``, ``p_value``, ``partial_r2``, ``starts``,
    ``scan`` and ``confounded`` filled in.

    Parameters that only mean something once the effect is present (``nuisance``, e.g. a second mass's time
    constant) are scanned and the largest score is kept (a sup-score test); the best points start the refits.
    Drops and swaps are not scored: they are always refitted (a swap unless confounded). ``jacobian`` and
    ``residual`` hold every ``stride``-th sample of each series (the base fit's
    :attr:`~thermolimb.identification.FreeRunLeastSquares.stride_`), and so does ``base_run``, the base
    model's free run if the caller has it: at its null an added effect is absent, so the extended model runs
    as the base (``tests/test_diagnosis.py::test_every_term_at_its_null_runs_as_the_base``) and is not
    simulated again.
    """
    if cand.kind in ("drop", "swap"):
        # from what the base fit left, and afresh (the base may sit where the old terms did the work)
        keep = {p.name for p in model_parameters(cand.model)}
        starts = ({k: v for k, v in base.params.items() if k in keep}, {})
        confounded = confounded_swap(cand, train) if cand.kind == "swap" else cand.confounded
        return replace(cand, starts=starts, p_value=0.0, confounded=confounded)
    term = cand.searched
    scored = []
    own_share = float("nan")
    at_null = simulate_all(base, train, stride) if base_run is None else base_run
    for fixed in _grid(term, train):
        score, p_value, r2, step, share, partner = _score_at(cand, term, base, train, jacobian, residual,
                                                             fixed, stride, at_null)
        own_share = np.fmax(own_share, share)
        scored.append((score, p_value, r2, {**dict(base.params), **step, **fixed}, partner))
    nuisance = [p.name for p in term.parameters if p.nuisance]
    scan = [({n: start[n] for n in nuisance}, start) for *_, start, _ in scored]
    scored.sort(key=lambda x: (x[4] is None, -x[0]))
    starts = [s[3] for s in scored[:REFIT_STARTS]]
    starts += [{**dict(base.params), **{p.name: p.typical for p in term.parameters}}]
    # at its null: no effect
    own = {p.name: p.typical for p in TERMS[cand.effect].parameters} if cand.brings else {}
    starts, scan = [{**s, **own} for s in starts], [(f, {**s, **own}) for f, s in scan]
    # times that are not nuisance (a sensor lag) start from the log's time scales too
    times = [p for p in term.parameters if p.unit == "s" and not p.nuisance]
    for scale in time_scales_s(train)[1:4:2] if times else ():
        starts.append({**dict(base.params),
                       **{p.name: float(np.clip(scale, p.lower, p.upper)) for p in times}})
    confounded = cand.confounded
    if not np.isfinite(own_share) or scored[0][4] is None:
        confounded = (f"{cand.effect} makes no difference on this log: it needs "
                      f"{term.parameters[0].excitation}")
    elif own_share < CONFOUNDED_FRACTION:
        confounded = (f"on this log {cand.effect} changes the simulation only as {scored[0][4]} already does "
                      f"({100 * own_share:.2g} % of its signature is its own): a log with "
                      f"{term.parameters[0].excitation} would tell them apart")
    return replace(cand, score=scored[0][0], p_value=scored[0][1], partial_r2=scored[0][2],
                   starts=tuple(starts), scan=tuple(scan), confounded=confounded)


def _score_at(cand, term, base, train, jacobian, residual, fixed, stride, at_null):
    values = dict(base.params)
    values.update({p.name: p.null for t in (cand.effect, *cand.brings) for p in TERMS[t].parameters})
    values.update(fixed)
    extended = ThermalModel(cand.model, values)
    primary = [p for p in term.parameters if not p.nuisance]
    columns = []
    for p in primary:
        step = 0.05 * abs(p.typical) if p.typical else 1e-3
        step = step if p.null + step <= p.upper else -step
        moved = extended.with_params({**extended.params, p.name: p.null + step})
        columns.append((simulate_all(moved, train, stride) - at_null) / step)
    S = np.column_stack(columns)
    coef, *_ = np.linalg.lstsq(jacobian, S, rcond=None)
    S_perp = S - jacobian @ coef
    size = np.linalg.norm(S)
    if not size > 1e-12 * max(np.linalg.norm(jacobian), 1.0):
        return 0.0, 1.0, 0.0, {p.name: p.null for p in primary}, float("nan"), None
    share = float(np.linalg.norm(S_perp) / size)
    names = [p.name for p in base.parameters]
    partner = names[int(np.argmax(np.abs(coef).sum(axis=1) * np.linalg.norm(jacobian, axis=0)))]
    null_step = {p.name: p.null for p in primary}
    if not np.any(np.abs(S_perp) > 0) or residual @ residual == 0:
        return 0.0, 1.0, 0.0, null_step, share, partner
    beta, *_ = np.linalg.lstsq(S_perp, residual, rcond=None)
    explained = S_perp @ beta
    r2 = float(explained @ explained / (residual @ residual))
    # serial correlation of what is left once the candidate explains its share: under the
    # alternative the left-over is the noise whose correlation discounts the sample count
    n_eff = residual.size / ar1_variance_factor(residual - explained)
    score = n_eff * r2
    # a Gauss-Newton step from the null, clipped into the bounds, starts the refit
    step = {p.name: float(np.clip(p.null + b, p.lower, p.upper)) for p, b in zip(primary, beta)}
    return score, chi2_sf(score, S.shape[1]), r2, step, share, partner


def bic(residual: np.ndarray, n_params: int) -> float:
    """BIC on the training residual; it overstates evidence for correlated residuals, which is why a
    recommendation also needs a held-out improvement."""
    return information_criteria(residual, n_params)["bic"]
