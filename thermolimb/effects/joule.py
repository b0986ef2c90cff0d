"""Joule heating from effort: Jorgensen et al.'s ``beta*R*F^2`` (Eq. 5), the base heat source.

The plant's own Joule heat (the current through the winding's resistance) is the network's base input, not a
switch; copper's rising resistance is :mod:`.winding_tempco`.
"""

from __future__ import annotations

import numpy as np

from ..model.terms import LinearTerm, Parameter, register_term
from .base import Effect, register


@register_term
class Joule(LinearTerm):
    """Effort-squared heating: Jorgensen et al.'s ``beta*R*F^2`` (Eq. 5)."""

    name = "joule"
    label = "Joule heating from effort"
    description = "Joule heating from effort squared (the base heat source)"
    parameters = (
        Parameter("betaR_K_per_effort2", "K/({effort})^2", 0.0, np.inf, 0.1,
                  "steady-state rise per squared effort, beta*R of Eq. 5",
                  "effort held at three or more distinct levels"),
    )
    is_heat_source = True
    squared_channel = "effort"

    def regressor(self, s):
        return s.effort**2


register(Effect("joule", Joule, residual="effort^2"))
