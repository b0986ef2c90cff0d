"""A series-elastic effort bias: the motor current makes ``effort - bias`` (Jorgensen et al., Eq. 2), so the
model gains a linear effort term ``-beta_bias*R*F`` (Eq. 5)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model.parameter_units import NOT_GIVEN
from ..model.terms import LinearTerm, Parameter, register_term
from .base import Effect, Hidden, PlantEffect, register


@register_term
class EffortBiasTerm(LinearTerm):
    """Linear effort term from a series-elastic effort bias: ``-beta_bias*R*F`` (Eq. 5)."""

    name = "effort_bias"
    label = "effort bias"
    description = "linear effort term (series-elastic bias of the torque-current map)"
    parameters = (
        Parameter("beta_biasR_K_per_effort", "K/({effort})", -np.inf, np.inf, 0.1,
                  "beta_bias*R of Eq. 5; positive when the bias lowers heating at positive effort",
                  "effort held at three or more distinct levels, ideally of both signs"),
    )

    def regressor(self, s):
        return -s.effort


MIN_RISE_K = 0.5  # a bias whose rise at the largest effort is smaller than this carries no heat worth judging
# efforts hold both signs when the lesser side reaches this share of the largest (at rest an
BOTH_SIGNS = 0.05
# effort reads noise about zero: the bundled step tests' 1st percentiles are -0.011 to +0.004 N m of 12-20)


def carries_the_heat(p, series, units) -> str | None:
    """Why a bias fitted beside Joule heating on ``series`` is implausible, or ``None``: the current makes
    ``effort - bias`` (Jorgensen et al., Eq. 2), so the Joule heat is least at the effort ``beta_biasR / (2
    betaR)``; where a log's efforts hold one sign (1st to 99th percentile) and that lies beyond the largest of
    them, the bias is no offset of the torque-current map but carries the heat itself, and would cool the
    joint wherever another duty pushes the other way, which the log cannot show (``benchmarks/transfer.py
    --step-K 1``, fitted on the walking duty); a change is judged so only where its base's bias did not carry
    the heat already (``judgement.judge``). A log with efforts of both signs (each side reaching
    ``BOTH_SIGNS`` of the largest, so that the noise of an effort at rest does not count) shows what the bias
    does at each, and is left to its held-out error (UR3 J5's wrist, whose bias rightly exceeds its ±0.3 N
    m)."""
    if "beta_biasR_K_per_effort" not in p or "betaR_K_per_effort2" not in p or not series:
        return None
    bias, joule = p["beta_biasR_K_per_effort"], p["betaR_K_per_effort2"]
    both, largest = both_signs(series)
    if both or abs(bias) * largest < MIN_RISE_K or abs(bias) <= 2.0 * joule * largest:
        return None  # efforts of both signs show what the bias does at each; a small bias, or one within them
    unit = (units or {}).get("effort", "")

    def effort(value: float) -> str:
        return f"{value:.3g} {unit}" if unit and unit != NOT_GIVEN else f"{value:.3g} (effort: {NOT_GIVEN})"

    if 2.0 * joule * 100.0 * largest > abs(bias):
        least = effort(bias / (2.0 * joule))
        where = f": Joule heating would be least at {least}, beyond the efforts the log holds, so"
    else:
        where = f", and Joule heating all but vanishes (betaR = {joule:.2g}):"
    return ("the effort bias carries the effort's heat "
            f"({abs(bias) * largest:.3g} K at {effort(largest)}, the log's "
            f"largest effort){where} the model would cool the joint at efforts of the other sign")


def both_signs(series) -> tuple[bool, float]:
    """Whether the efforts of ``series`` hold both signs (1st and 99th percentiles each side of zero, the
    lesser reaching ``BOTH_SIGNS`` of the larger), and the larger's magnitude."""
    low, high = np.percentile(np.concatenate([s.signals.effort for s in series]), [1, 99])
    largest = max(abs(low), abs(high))
    return bool(min(-low, high) >= BOTH_SIGNS * largest), float(largest)


@dataclass(frozen=True)
class EffortBias(PlantEffect):
    """Series-elastic bias: the motor current makes ``effort - bias_effort`` (Jorgensen et al., Eq. 2)."""

    name = "effort_bias"
    bias_effort: float = 2.0  # N m (or N)

    def torque_effort(self, effort):
        return effort - self.bias_effort


# in the default start model: found means kept; a log that carries the motor's current has the bias in it (the
# current makes effort - bias), so heat from the current names the same physics
register(Effect("effort_bias", EffortBiasTerm, EffortBias, residual="effort",
                hidden=Hidden("effort_bias", "effort_bias", also=("current_heating",))))
