"""The test that tells two explanations apart (``thermolimb plan --separate A,B``).

A log may leave two effects confounded: on it one changes the simulated readings only as the other already
does.  The question is then not a parameter's size but which of two models the joint follows: the model file's
(with ``A``) or its rival (``B`` beside it, or in its place where both are heat sources, at ``B``'s typical
values: the first log could not size it).  :func:`separate` designs the test, within the same profile family
and limits as :func:`~thermolimb.experiment.design`, that maximises the part of the two models' difference
the model file's own parameters (and hidden states' starts) cannot absorb: with ``d`` the rival's free run
less the model's over the samples a fit compares, and ``S`` the model's sensitivities,
``||(I - S S^+) d||^2 / sigma^2`` (the linearised noncentrality of the test between them: Atkinson and
Fedorov's T-optimality).  The winding is kept under the limit less the margin by the model's forecast band
and by the rival's prediction plus the model's held-out error.

It promises the separation: the rms of that part of the difference (K) and its size against the readings'
noise.  What it assumes: the rival's size is near its parameters' typical values (a guess, said), and the
model's structure is right but for the question.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from .experiment import COARSE_PER_HOLD, SUPPORTED, DesignProblem, Limits, Plan, planned, posed
from .forecast import forecast
from .model.model import ThermalModel, model_parameters
from .model.saved import SavedModel
from .model.terms import TERMS
from .util.errors import ThermolimbError


def rival(saved: SavedModel, pair) -> tuple[SavedModel, str, str]:
    """The rival model of the question ``pair`` (two term names, one in ``saved``'s model): ``(rival, held,
    other)``, the other term beside the held one, or in its place where both are heat sources, at its typical
    values."""
    a, b = pair
    terms = saved.model.terms
    if (a in terms) == (b in terms) or a not in TERMS or b not in TERMS:
        named = ", ".join(t for t in pair if t not in TERMS)
        raise ThermolimbError(
            f"--separate {a},{b}: " + (f"no term {named}; expected terms such as {', '.join(list(TERMS)[:4])}"
                                       if named else
                                       f"expected one term the model ({','.join(terms)}) has and one it "
                                       f"lacks"))
    held, other = (a, b) if a in terms else (b, a)
    unread = [c for c in TERMS[other].columns if c not in SUPPORTED]
    if unread:
        raise ThermolimbError(f"--separate {a},{b}: {other} reads the log column {unread[0]!r}, which a "
                              f"planned test does not set (it sets effort and velocity): a question a plan "
                              f"cannot pose")
    swap = TERMS[held].is_heat_source and TERMS[other].is_heat_source
    model = tuple(other if t == held else t for t in terms) if swap else terms + tuple(
        r for r in TERMS[other].requires if r not in terms) + (other,)
    params = {p.name: saved.model.params.get(p.name, p.typical) for p in model_parameters(model)}
    return replace(saved, model=ThermalModel(model, params)), held, other


class SeparationProblem(DesignProblem):
    """The design problem whose cost is the separation of the model from ``rival`` (module docstring)."""

    def __init__(self, base: DesignProblem, rival_model: ThermalModel):
        super().__init__(base.saved, base.t, base.edges, base.holds, base.limits, base.noise, (), base.signed,
                         base.moves, base.weight, base.lag1)
        self.rival = rival_model

    def coarse(self, per_hold: int = COARSE_PER_HOLD) -> "SeparationProblem":
        return SeparationProblem(super().coarse(per_hold), self.rival)

    def part(self, x) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The part of the rival's difference the model cannot absorb (over the fitted samples), the model's
        free run and its sensitivities."""
        base, S, H = self.sensitivities(x)
        d = (self.rival.simulate(self.signals(x), self.limits.start_C) - base)[self.fit]
        columns = np.hstack([S[self.fit], H[self.fit]])
        scale = np.linalg.norm(columns, axis=0)
        columns = columns[:, scale > 0] / scale[scale > 0]
        return d - columns @ np.linalg.lstsq(columns, d, rcond=None)[0], base, S

    def cost(self, x) -> float:
        left, base, S = self.part(x)
        spread = np.sqrt(np.einsum("ij,jk,ik->i", S, np.asarray(self.saved.covariance, float), S).clip(0.0))
        hottest = max(np.max(base + self.margin + 1.645 * spread),
                      np.max(self.rival.simulate(self.signals(x), self.limits.start_C)) + self.margin)
        over = hottest - self.ceiling
        return -float(np.log(self.weight * np.sum(left**2) / self.noise**2 + 1e-300)) + (
            1e3 * over**2 if over > 0 else 0.0)

    def checked(self, x):
        for _ in range(60):
            band = forecast(self.saved, self.signals(x), self.limits.start_C, self.limits.limit_C)
            other = self.rival.simulate(self.signals(x), self.limits.start_C) + self.margin
            if max(np.max(band.high_C), np.max(other)) <= self.ceiling:
                return x, band
            x = x * 0.95
        raise ThermolimbError(f"no test within --max-effort keeps both models' winding under "
                              f"{self.ceiling:g} degC; expected a lower start or a higher limit")


def separate(saved: SavedModel, pair, limits: Limits, noise_K: float | None = None, seed: int = 0) -> Plan:
    """The test that best tells ``saved``'s model from its rival in ``pair`` within ``limits`` (module
    docstring).

    Returns
    -------
    Plan
        The profile, its predicted and upper-band temperatures, and the separation it promises instead of
        standard errors: ``separation_K`` (rms K of the rival's difference the model's parameters cannot
        absorb, over the fitted samples) and ``separation_sigma`` (its norm against the readings' noise).
    """
    other_saved, held, other = rival(saved, pair)
    base, notes = posed(saved, (), limits, noise_K)
    problem = SeparationProblem(base, other_saved.model)
    best = problem.coarse().search(np.random.default_rng(seed))
    x, _ = problem.checked(best)
    left, _, _ = problem.part(x)
    typical = ", ".join(f"{p.name} {p.typical:g}" for p in TERMS[other].parameters)
    notes.append(f"{other} is taken at its parameters' typical values ({typical}): the first log could not "
                 f"size it, and the separation holds as well as that guess")
    return planned(problem, x, notes, separate=(held, other),
                   separation_K=float(np.sqrt(np.mean(left**2))),
                   separation_sigma=float(np.sqrt(np.sum(left**2)) / problem.noise))
