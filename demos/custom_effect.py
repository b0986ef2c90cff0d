"""Demo ``custom-effect``: write your own effect in a few lines, and ``diagnose`` ranks it.

The motor (a plant run) weakens its field above a base speed: d-axis current
flows that makes no torque and heats the winding.  The log has no current
column, so the catalog's ``current_heating`` cannot see it.  The user does
not know the plant's law; they suspect "extra heat that grows steeply with
speed" and write the most plausible thing: heat growing as a power of speed,
``k |v|^n``, with the exponent ``n`` left for the fit.  It is registered, the
diagnosis runs again, and the demo reports honestly how far it gets: against
the catalog alone (``speed_losses``, ``k1 |v| + k2 v^2``), and against the
physics the plant really has (current squared, once current is logged).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from thermolimb.demo_registry import DemoPage, demo_main, kelvin, register_demo
from thermolimb.logs import from_frame
from thermolimb.model import Parameter, Term, register_term, unregister_term
from thermolimb.plant import NETWORKS, PlantEffects, simulate_profile
from thermolimb.plant.cases import CASE_NAMES, CASE_SPECS
from thermolimb.plotting.diagnosis import plot_diagnosis
from thermolimb.workbench.diagnosis import auto_diagnose

NAME = "custom-effect"


class SpeedPowerHeating(Term):
    """Heat growing as a power of speed: ``k |v|^n`` (the exponent is fitted, between 1 and 6)."""

    name = "speed_power_heating"
    description = "extra heat growing as a power of speed"
    parameters = (
        Parameter("k_K_per_speed_n", "K/(rad/s)^n", 0.0, np.inf, 0.5, "rise at 1 rad/s", "motion at several speeds"),
        Parameter("speed_exponent", "1", 1.0, 6.0, 3.0, "how steeply the heat grows with speed",
                  "motion at several speeds", null=3.0, nuisance=True),
    )
    columns = ("velocity",)

    def contribution(self, p, s):
        return p["k_K_per_speed_n"] * np.abs(s.channel("velocity")) ** p["speed_exponent"], 0.0


def _walk(first) -> list[dict]:
    return [{"change": step.get("change", "start"), "model": step["model"], "rmse_K": step["rmse_K"]}
            for step in first.auto]


def _headline(summary: dict) -> list[tuple[str, str, str]]:
    rows = []
    for key, label in (("catalog_only", "catalogue terms only"), ("with_user_effect", "with the user's effect"),
                       ("with_current_logged", "with the current logged")):
        steps = summary[key]
        rows.append((f"validation RMSE, {label}", kelvin(steps[-1]["rmse_K"]),
                     f"from {kelvin(steps[0]['rmse_K'])} ({', '.join(s['change'] for s in steps[1:]) or 'no change'})"))
    p = summary["user_effect_params"]["speed_exponent"]
    rows.append(("fitted speed exponent", f"{p['value']:.2f} ± {p['stderr']:.2g}", "the user's power law"))
    return rows


def _finding(summary: dict) -> str:
    ends = {key: summary[key][-1]["rmse_K"] for key in ("catalog_only", "with_user_effect", "with_current_logged")}
    return (f"In this run the held-out error falls from {kelvin(summary['catalog_only'][0]['rmse_K'])} to "
            f"{kelvin(ends['catalog_only'])} with the catalogue alone, to {kelvin(ends['with_user_effect'])} with the "
            f"user's effect, and to {kelvin(ends['with_current_logged'])} with the current logged.")


PAGE = DemoPage(
    about="Heating that grows with a power of speed, which no catalogue term has. The stepwise search runs three "
          "times: with the catalogue alone, with a user-written effect registered in a few lines, and with the "
          "current logged. Look at the waterfall: the catalogue gets part of the way, the user's effect reaches "
          "the noise floor, and logging the current makes the question moot.",
    headline=_headline,
    finding=_finding)


@register_demo(NAME, "a user-written effect, registered in a few lines, ranked by diagnose like the built-ins",
               page=PAGE)
def run(out: Path, quick: bool = False, quiet: bool = True) -> dict:
    effects = PlantEffects.from_names("sensor_noise,quantisation,field_weakening")
    log = simulate_profile("random", (1 if quick else 2) * 3600.0, 1.0, list(CASE_NAMES),
                           list(CASE_SPECS), effects, seed=2, network=NETWORKS["first_order"], quiet=quiet).log
    no_current = [from_frame(log.frame.drop(columns="current")).series("knee")]
    catalog, _ = auto_diagnose(no_current, quiet=quiet)
    register_term(SpeedPowerHeating)
    try:
        user, steps = auto_diagnose(no_current, quiet=quiet)
        plot_diagnosis(user, out, "knee")
        final = steps[-1].base.to_json()
    finally:
        unregister_term(SpeedPowerHeating.name)
    truth, _ = auto_diagnose([log.series("knee")], quiet=quiet)
    return {
        "catalog_only": _walk(catalog),
        "with_user_effect": _walk(user),
        "with_current_logged": _walk(truth),
        "user_effect_params": final["params"] if SpeedPowerHeating.name in final["model"] else None,
    }


def main(argv=None) -> dict:
    return demo_main(NAME, argv)


if __name__ == "__main__":
    main()
