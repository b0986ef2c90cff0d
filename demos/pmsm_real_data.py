"""Demo ``pmsm-real-data``: the diagnosis on real motor measurements (Paderborn PMSM test bench).

Torque is only a proxy for what heats a motor: current does, and at high
speed field weakening drives current that makes no torque.  Starting from
the default model (torque squared and the linear bias term), the stepwise
search on profiles 24 and 46 drops what extrapolates badly, swaps torque for
current and adds what is missing; blocked cross-validation checks profile
24, whose training part holds torque and current nearly constant.
"""

from __future__ import annotations

from pathlib import Path

from thermolimb.data import PMSM_MAP, pmsm_profile
from thermolimb.demo_registry import demo_main, register_demo
from thermolimb.diagnosis import auto_diagnose
from thermolimb.diagnosis.plots import plot_diagnosis
from thermolimb.logs import parse_mapping, read_log
from thermolimb.model.terms import DEFAULT_MODEL

NAME = "pmsm-real-data"


@register_demo(NAME, "real PMSM test-bench data: what torque-squared heating misses, and what closes the gap")
def run(out: Path, quick: bool = False, quiet: bool = True) -> dict:
    summary = {"source": "Paderborn University 'Electric Motor Temperature' data, CC BY-SA 4.0",
               "base_model": list(DEFAULT_MODEL), "profiles": {}}
    for number in (24, 46):
        log = read_log(pmsm_profile(number), mapping=parse_mapping(PMSM_MAP), velocity_unit="rpm")
        series = [log.series(f"profile{number}")]
        first, _ = auto_diagnose(series, quiet=quiet)
        plot_diagnosis(first, out, f"profile{number}")
        entry = {"split": {"waterfall": first.auto, "recommended_model": first.to_json()["recommended_model"]}}
        if number == 24:
            cv, _ = auto_diagnose(series, cv=4, quiet=quiet)
            entry["cv4"] = {"waterfall": cv.auto}
        summary["profiles"][f"profile{number}"] = entry
    return summary


def main(argv=None) -> dict:
    return demo_main(NAME, argv)


if __name__ == "__main__":
    main()
