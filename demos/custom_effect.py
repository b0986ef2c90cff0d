"""Demo ``custom-effect``: write your own effect in a few lines, and ``diagnose`` ranks it.

A motor weakens its field above a base speed: d-axis current flows that makes
no torque, and heats the winding.  With a current column the catalog's
``current_heating`` sees it; this log has no current column.  The user knows
the physics, so writes the effect -- heat growing with the squared speed in
excess of a base speed -- as a :class:`~thermolimb.model.Term`, registers
it, and diagnoses again: it is ranked with the built-ins and closes the gap
that the catalog's ``speed_losses`` only narrows.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from thermolimb.demo_registry import demo_main, register_demo
from thermolimb.diagnosis import diagnose
from thermolimb.diagnosis.plots import plot_diagnosis
from thermolimb.logs import from_frame
from thermolimb.model import Parameter, Term, register_term, unregister_term
from thermolimb.plant import NETWORKS, X8_9, X8_16, PlantEffects, simulate_profile

NAME = "custom-effect"


class FieldWeakeningBySpeed(Term):
    """Heat from field-weakening current, from speed alone: ``k * max(|v| - v0, 0)^2``."""

    name = "field_weakening_speed"
    description = "field-weakening heat above a base speed (no current column needed)"
    parameters = (
        Parameter("fw_K_per_rad2_s2", "K/(rad/s)^2", 0.0, np.inf, 2.0, "rise per squared excess speed",
                  "motion above the base speed"),
        Parameter("fw_base_speed_rad_s", "rad/s", 0.0, 3.0, 0.8, "speed where field weakening starts",
                  "motion above the base speed", null=0.8, nuisance=True),
    )
    columns = ("velocity",)

    def contribution(self, p, s):
        excess = np.maximum(np.abs(s.channel("velocity")) - p["fw_base_speed_rad_s"], 0.0)
        return p["fw_K_per_rad2_s2"] * excess**2, 0.0


@register_demo(NAME, "a user-written effect, registered in a few lines, ranked by diagnose like the built-ins")
def run(out: Path, quick: bool = False, quiet: bool = True) -> dict:
    effects = PlantEffects.from_names("sensor_noise,quantisation,field_weakening")
    log = simulate_profile("random", 2 * 3600.0, 1.0, ["knee", "hip", "ankle"], [X8_9, X8_16, X8_9], effects,
                           seed=2, network=NETWORKS["first_order"], quiet=quiet).log
    no_current = from_frame(log.frame.drop(columns="current"))
    series = [no_current.series("knee")]
    before = diagnose(series, quiet=quiet)
    register_term(FieldWeakeningBySpeed)
    try:
        after = diagnose(series, quiet=quiet)
    finally:
        unregister_term(FieldWeakeningBySpeed.name)
    plot_diagnosis(after, out, "knee")
    return {"catalog_only": before.to_json(), "with_user_effect": after.to_json()}


def main(argv=None) -> dict:
    return demo_main(NAME, argv)


if __name__ == "__main__":
    main()
