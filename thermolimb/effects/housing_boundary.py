"""A second sensor on the housing: the winding loses heat to its measured housing, so the slow thermal masses
need not be modelled.  The plant hides it by logging a thermistor on each actuator's housing node
(``run_profile(housing_sensor=True)``)."""

from __future__ import annotations

from ..model.terms import LinearTerm, Parameter, register_term
from .base import Effect, Hidden, register


@register_term
class HousingBoundary(LinearTerm):
    """The winding loses heat to its measured housing: ``g T_housing`` replaces most of the constant offset.

    With a second sensor on the housing (case, stator body, driver board) the
    slow thermal masses need not be modelled: their temperature is measured.
    ``T_offset`` then holds what the housing does not explain (``(1 - g)`` of ambient).
    """

    name = "housing_boundary"
    label = "housing as the boundary"
    description = "the winding's boundary is the measured housing temperature (a second sensor)"
    parameters = (
        Parameter("housing_gain", "1", 0.0, 1.5, 0.9,
                  "kelvin of winding equilibrium per kelvin of "
                  "housing (1: all heat leaves through the housing)",
                  "a housing temperature that moves during the log", plausible=(0.3, 1.2)),
    )
    columns = ("housing",)
    redefines_offset = True

    def regressor(self, s):
        return s.channel("housing")


register(Effect("housing_boundary", HousingBoundary, residual="housing temperature",
                hidden=Hidden("housing_sensor", None, options={"housing_sensor": True}), rides="housing"))
