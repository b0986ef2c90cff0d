"""Copper's resistance rising with temperature: the Joule heat times ``1 + alpha (T - 25 degC)``, visible when
the winding runs hot."""

from __future__ import annotations

from dataclasses import dataclass

from ..constants import COPPER_REFERENCE_C, COPPER_TEMPCO_PER_K
from ..model.terms import Parameter, Term, register_term
from .base import HOT_AND_COOL, Effect, Hidden, PlantEffect, register


@register_term
class WindingTempcoTerm(Term):
    """Copper resistance rising with temperature: the Joule terms times ``1 + alpha (T - 25 degC)``."""

    name = "winding_tempco"
    reads = ("betaR_K_per_effort2", "currentR_K_per_A2")  # the Joule heat it scales
    scales_resistance = True
    label = "copper's temperature coefficient"
    description = "copper resistance rising with winding temperature"
    parameters = (
        Parameter("alpha_per_K", "1/K", -0.01, 0.02, 0.004,
                  "temperature coefficient of the winding resistance (copper: about 0.0039/K)",
                  "hot and cool phases at the same effort", plausible=(0.002, 0.006)),
    )

    def forms(self, s):  # the winding's readings moved to another air (Signals.air_shift_K) are added back
        return s.effort**2, (None if s.current_A is None else s.current_A**2), s.air_shift_K

    def combine(self, p, forms):
        effort2, current2, air_shift_K = forms
        joule = 0.0
        if "betaR_K_per_effort2" in p:
            joule = joule + p["betaR_K_per_effort2"] * effort2
        if "currentR_K_per_A2" in p and current2 is not None:
            joule = joule + p["currentR_K_per_A2"] * current2
        alpha = p["alpha_per_K"]
        return -alpha * (COPPER_REFERENCE_C - air_shift_K) * joule, alpha * joule


@dataclass(frozen=True)
class WindingTempco(PlantEffect):
    """Copper resistance rising with winding temperature: R = R25 (1 + alpha (T - 25 degC))."""

    name = "winding_tempco"
    state_dependent = True
    alpha_per_K: float = COPPER_TEMPCO_PER_K
    reference_C: float = COPPER_REFERENCE_C

    def place_joule(self, net, joule, constant, per_kelvin):
        constant[..., net.winding] += joule * (1.0 - self.alpha_per_K * self.reference_C)
        per_kelvin[..., net.winding] += joule * self.alpha_per_K
        return True


# visible only when hot: a heavier load
register(Effect("winding_tempco", WindingTempcoTerm, WindingTempco, residual=HOT_AND_COOL,
                hidden=Hidden("winding_tempco", "winding_tempco", load_scale=1.8)))
