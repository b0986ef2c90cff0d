"""The stages a diagnosis and a stability replicate share: the base fit's record, the screen of the changes
worth trying, the refits' order.

A diagnosis (:mod:`.diagnose`) runs base -> screen -> refits -> judgement -> stability -> verdict; a stability
replicate (:mod:`.replicate`) runs base -> screen -> refits on a perturbed copy of the log, over the changes
that contended on the whole log, and returns the label it takes.  Both call these functions; neither is a
branch of the other.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ...effects import EFFECTS
from ...identification.thinning import thinned
from ...logs import ActuatorSeries
from ...model.terms import TERMS
from ...util.errors import TermError
from ..excitation import channel_excitation
from ..submodel import from_effort_alone, within_levels
from ..validation import FitReport
from .candidates import Candidate, bic, candidate_models, score_candidate
from .channels import channel_candidates
from .refit import set_aside


@dataclass(frozen=True)
class Base:
    """The base stage's record: the model fitted and validated on the log (``report``), its BIC on the
    training residual, and what a score test needs of it -- the training runs, the stride its fit compared at,
    the residual and the Jacobian at that stride, and the free run an added effect at its null repeats
    (``None`` where the
    model places hidden states per run: the score test's signatures are then taken from such free runs)."""

    report: FitReport
    bic: float
    train: tuple[ActuatorSeries, ...]
    stride: int
    residual: np.ndarray
    jacobian: np.ndarray
    free_run: np.ndarray | None

    @property
    def model(self) -> tuple[str, ...]:
        return self.report.model.terms

    @property
    def rmse_K(self) -> float:
        """The base model's held-out error."""
        return self.report.validation["rmse_K"]

    @classmethod
    def of(cls, report: FitReport) -> "Base":
        """The record of a fitted, validated model (the search's base fit, or a refitted change's report)."""
        train = tuple(report.train_series)
        stride = report.estimator.stride_
        free_run = None
        if not report.model.hidden_states:
            simulated = np.concatenate([s.simulated_C for s in report.train_segments])
            free_run = thinned(simulated, list(train), stride)
        residual = thinned(report.train_residual_K, list(train), stride)
        return cls(report, bic(report.train_residual_K, len(report.model.params)), train, stride, residual,
                   report.estimator.jacobian_, free_run)

    def first_run(self) -> tuple[ActuatorSeries, np.ndarray]:
        """The first run fitted on, whole (its blocks held out too: a continuous free run to correlate), and
        the
        model's free run on it: the residual the evidence is worded from."""
        run0 = replace(self.train[0], fit_mask=None)
        offsets = getattr(self.report.estimator, "offsets_", None)
        return run0, self.report.model.free_run(run0, offsets=offsets[0] if offsets else None)


def changes(model: tuple[str, ...], base: Base, series: list[ActuatorSeries], discover: bool,
            held_out: tuple = (), skip: frozenset = frozenset(),
            visited: frozenset = frozenset()) -> list[Candidate]:
    """The changes worth trying on ``model`` fitted as ``base``: the catalog's additions, drops and swaps
    (:func:`~.candidates.candidate_models`), with ``discover`` the log's extra channels' forms
    (:func:`~.channels.channel_candidates`, on ``series`` and the ``held_out`` runs); none labelled in
    ``skip`` (confounded at an earlier step), none leading to a model in ``visited``."""
    candidates = candidate_models(model, series[0])
    if discover:
        candidates += channel_candidates(model, list(base.train), series + list(held_out))
    return [c for c in candidates if c.label not in skip and frozenset(c.model) not in visited]


def screened(candidates: list[Candidate], base: Base) -> list[Candidate]:
    """The screen: each change's score test against ``base`` (its signature, confounding), and whether the
    data excite the channel it rides on (:func:`unexcited`); new records, in the same order."""
    return [unexcited(_scored(cand, base), base.report) for cand in candidates]


def _scored(cand: Candidate, base: Base) -> Candidate:
    try:
        return score_candidate(cand, base.report.model, list(base.train), base.jacobian, base.residual,
                               base.stride, base.free_run)
    except TermError as exc:
        return set_aside(cand, exc)


def unexcited(cand: Candidate, base: FitReport) -> Candidate:
    """``cand``, not judged where it brings in an effect riding on a channel (velocity, current, a neighbour's
    temperature, a logged extra) that does not move in the data it is fitted on and in the data it is judged
    on (:func:`~thermolimb.workbench.excitation.channel_excitation`), saying why with the counts.  Nor is one
    bringing back heat from the effort alone that the log's effort cannot pin beside the model's
    (:func:`~thermolimb.workbench.submodel.within_levels`: the bias on a step test)."""
    if cand.kind == "drop" or cand.confounded is not None:
        return cand
    aside: list = []  # a term of heat from the effort alone this log's effort cannot tell from the model's
    effect = cand.effect
    if from_effort_alone(effect) and effect not in within_levels(cand.model, base.train_series, aside):
        why = next(a["reason"] for a in aside if a["term"] == cand.effect)
        return replace(cand, unexcited=why, evidence=f"not judged: {why}.")
    # a pair's members: each its own channel
    for channel in filter(None, map(rides, (*cand.brings, cand.effect))):
        counts = channel_excitation(channel, base.train_series,
                                    [(seg.signals, seg.measured_C) for seg in base.validation_segments])
        if not counts.excited:
            return replace(cand, unexcited=counts.sentence(), evidence=f"not judged: {counts.sentence()}.")
    return cand


def rides(effect: str) -> str | None:
    """The channel an effect rides on: its :class:`~thermolimb.effects.Effect`'s, or for a term of the log's
    channels (a generated one, a user's) the first column it reads beyond the effort."""
    if effect in EFFECTS:
        return EFFECTS[effect].rides
    return next((c for c in TERMS[effect].columns if c != "effort"), None)


def judgeable(candidates: list[Candidate]) -> list[Candidate]:
    """The screened changes a refit can judge: not confounded, not set aside, on a channel the data excite."""
    return [c for c in candidates if c.confounded is None and c.broken is None and c.unexcited is None]


def rank(c: Candidate):
    """Eligible changes by held-out gain, then the other refitted ones by gain, confounded, then the rest by
    score."""
    if c.refitted:
        return (0 if c.eligible else 1, -c.improvement, 0.0)
    return (2 if c.confounded is None else 3, 0.0, -c.score)


def best_eligible(candidates: list[Candidate]) -> Candidate | None:
    """The first of the ranked changes where it is eligible, else ``None``."""
    return candidates[0] if candidates and candidates[0].eligible else None
