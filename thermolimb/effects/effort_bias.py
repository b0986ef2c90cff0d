"""A series-elastic effort bias: the motor current makes ``effort - bias`` (Jorgensen et al., Eq. 2), so the
model gains a linear effort term ``-beta_bias*R*F`` (Eq. 5)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

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
