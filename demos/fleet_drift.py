"""Demo ``fleet-drift``: a fleet fitted at once, and the actuator whose parameters move between runs.

Part one is a fleet from the plant: six actuators over four one-hour runs,
where one actuator's thermal resistance to ambient rises by half after the
second run (a failing fan); every actuator's every run is fitted over the
process pool, and the drift test should flag that one actuator alone.  Part
two is the UR3 cobot's six joints over the two parts of its real log
(CC BY 4.0), fitted the same way: what moves there, and why it cannot be
read as a fault without more runs.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from thermolimb.data import REAL_LOGS
from thermolimb.demo_registry import DemoPage, demo_main, register_demo
from thermolimb.model import DEFAULT_MODEL
from thermolimb.plant import (
    FIRST_ORDER_NETWORK,
    X8_9,
    PlantEffects,
    Quantisation,
    SensorNoise,
    ThermalPlant,
    run_profile,
)
from thermolimb.plant.profiles import random_holds
from thermolimb.plotting.drift import plot_drift
from thermolimb.workbench.drift import drift
from thermolimb.workbench.fleet import fit_fleet

NAME = "fleet-drift"
MODEL = DEFAULT_MODEL
ACTUATORS = tuple(f"a{k}" for k in range(6))
FAILING = "a3"
RESISTANCE_FACTOR = 1.5


def plant_fleet(runs: int, duration_s: float, seed: int = 0) -> list:
    """``runs`` logs of six first-order X8 actuators; ``FAILING``'s resistance rises by half from run 3 on."""
    healthy = replace(X8_9, network=FIRST_ORDER_NETWORK)
    hot = replace(healthy, network=replace(FIRST_ORDER_NETWORK, resistance_K_per_W=tuple(
        RESISTANCE_FACTOR * r for r in FIRST_ORDER_NETWORK.resistance_K_per_W)))
    logs = []
    for run in range(runs):
        rng = np.random.default_rng(seed + run)
        specs = [hot if (name == FAILING and run >= 2) else healthy for name in ACTUATORS]
        plant = ThermalPlant(list(ACTUATORS), specs,
                             PlantEffects(sensor_noise=SensorNoise(), quantisation=Quantisation()), rng=rng)
        log = run_profile(plant, random_holds(duration_s, 1.0, len(ACTUATORS), rng)).log
        logs.append(replace(log, source=f"plant_run{run + 1}"))
    return logs


def _summary(records: list[dict]) -> dict:
    return {r["actuator"]: {"flagged": r["flagged"], "why": r["why"],
                            "RC_s": r["params"]["RC_s"]["values"] if "RC_s" in r["params"] else None}
            for r in records}


def _headline(summary: dict) -> list[tuple[str, str, str]]:
    plant, ur3 = summary["plant"], summary["ur3"]
    flagged = [a for a, r in plant["drift"].items() if r["flagged"]]
    rc = plant["drift"][plant["failing"]]["RC_s"]
    return [("plant fleet: actuators flagged", ", ".join(flagged) or "none",
             f"the fan fails on {plant['failing']} only (resistance ×{plant['resistance_factor']:g} from run 3)"),
            (f"plant fleet: {plant['failing']}'s RC by run", " · ".join(f"{v:.0f} s" for v in rc),
             "RC = R C rises with the resistance"),
            ("UR3: joints flagged", ", ".join(a for a, r in ur3["drift"].items() if r["flagged"]) or "none",
             f"{len(ur3['drift'])} joints, two parts of one day's log"),
            ("rows fitted", f"{plant['rows']} plant, {ur3['rows']} UR3", "one per actuator and run, process pool")]


def _finding(summary: dict) -> str:
    plant = summary["plant"]
    flagged = [a for a, r in plant["drift"].items() if r["flagged"]]
    return (f"In this run the drift test flags {', '.join(flagged) or 'no actuator'} of {len(plant['drift'])} on the "
            f"plant fleet, where the fan fails on {plant['failing']} only.")


PAGE = DemoPage(
    about="A fleet fitted at once: every actuator's every run identified on its own over the process pool, then "
          "each actuator's RC, βR and offset compared across its runs. On the plant fleet one actuator's fan "
          "fails after the second run and the drift test flags it alone. On the UR3's real log the joints' "
          "parameters also move between the two parts of the day — there the model is incomplete (heat from "
          "neighbours, changing tasks), so movement beyond the standard errors is a prompt to look, not a "
          "diagnosis of a fault.",
    headline=_headline,
    finding=_finding,
    captions={"drift_plant.png": "Plant fleet: each actuator's estimates run by run (2-σ bars); flagged actuators "
                                 "named in red.",
              "drift_ur3.png": "UR3: each joint's estimates over the two parts of the log."})


@register_demo(NAME, "a fleet fitted at once: rows per actuator and run, and the actuator whose parameters drift",
               page=PAGE)
def run(out: Path, quick: bool = False, quiet: bool = True) -> dict:
    logs = plant_fleet(4, 1800.0 if quick else 3600.0)
    rows = fit_fleet(logs, MODEL)
    records = drift(rows)
    plot_drift(records, out / "drift_plant.png", effort_unit=logs[0].units.get("effort"))
    ur3_logs = REAL_LOGS["ur3"].read()
    ur3_rows = fit_fleet(ur3_logs, MODEL)
    ur3 = drift(ur3_rows)
    plot_drift(ur3, out / "drift_ur3.png", effort_unit=ur3_logs[0].units.get("effort"))
    return {"plant": {"failing": FAILING, "resistance_factor": RESISTANCE_FACTOR, "rows": len(rows),
                      "drift": _summary(records)},
            "ur3": {"rows": len(ur3_rows), "drift": _summary(ur3)},
            "details": {"plant_rows": rows, "ur3_rows": ur3_rows}}


def main(argv=None) -> dict:
    return demo_main(NAME, argv)


if __name__ == "__main__":
    main()
