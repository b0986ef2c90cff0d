"""Demo ``pmsm-real-data``: the diagnosis on real motor measurements (Paderborn PMSM test bench).

Torque is only a proxy for what heats a motor: current does, and at high
speed field weakening drives current that makes no torque.  Starting from
torque-squared heating (``joule``), the diagnosis of profiles 24 and 46
finds what the model misses; blocked cross-validation checks profile 24,
whose training part holds torque and current nearly constant.
"""

from __future__ import annotations

from pathlib import Path

from thermolimb.data import PMSM_MAP, pmsm_profile
from thermolimb.demo_registry import demo_main, register_demo
from thermolimb.diagnosis import auto_diagnose, diagnose
from thermolimb.diagnosis.plots import plot_diagnosis
from thermolimb.logs import parse_mapping, read_log

NAME = "pmsm-real-data"


@register_demo(NAME, "real PMSM test-bench data: what torque-squared heating misses, and what closes the gap")
def run(out: Path, quick: bool = False, quiet: bool = True) -> dict:
    summary = {"source": "Paderborn University 'Electric Motor Temperature' data, CC BY-SA 4.0",
               "base_model": ["joule"], "profiles": {}}
    for number in (24, 46):
        log = read_log(pmsm_profile(number), mapping=parse_mapping(PMSM_MAP), velocity_unit="rpm")
        series = [log.series(f"profile{number}")]
        first, _ = auto_diagnose(series, model="joule", quiet=quiet)
        plot_diagnosis(first, out, f"profile{number}")
        entry = {"split": {"waterfall": first.auto, "recommended_model": first.to_json()["recommended_model"]}}
        if number == 24:
            cv = diagnose(series, model="joule", cv=4, quiet=quiet)
            entry["cv4"] = {"base_rmse_K": cv.base.validation["rmse_K"],
                            "recommended_model": cv.to_json()["recommended_model"],
                            "recommended_rmse_K": cv.recommended.rmse_K if cv.recommended else None}
        summary["profiles"][f"profile{number}"] = entry
    return summary


def main(argv=None) -> dict:
    return demo_main(NAME, argv)


if __name__ == "__main__":
    main()
