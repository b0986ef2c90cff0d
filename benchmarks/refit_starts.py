"""Do a candidate's refits end at the same optimum whatever they start from?

For each log (the UR3's joints 2, 4 and 5, PMSM profile 46, and a plant log with speed losses hidden), the
diagnosis from Jorgensen et al.'s model is run once; then every change it refitted is refitted again from
``--starts`` other starting points: its fitted values each scaled by a factor drawn log-uniformly from 1/3 to 3
(seeded), as the stability replicates scale theirs, but three times wider.  Reported per change: the validation
RMSE of each refit and their spread, (max - min) / min.  The target: within 1 %.

    python benchmarks/refit_starts.py [--starts 6] [--json]
"""

from __future__ import annotations

import argparse
import json

import numpy as np

from thermolimb.data import PMSM_MAP, PMSM_UNITS, REAL_LOGS, pmsm_profile
from thermolimb.logs import parse_mapping, read_log
from thermolimb.plant import NETWORKS, PlantEffects, simulate_profile
from thermolimb.plant.cases import CASE_NAMES, CASE_SPECS
from thermolimb.workbench.diagnosis import diagnose
from thermolimb.workbench.diagnosis.candidates import Candidate
from thermolimb.workbench.diagnosis.refit import refit_candidate
from thermolimb.workbench.validation import Scheme


def logs() -> list[tuple[str, list]]:
    ur3 = REAL_LOGS["ur3"].read()[0]
    out = [(f"UR3 {j}", ur3.runs(j)) for j in ("J2", "J4", "J5")]
    log = read_log(pmsm_profile(46), mapping=parse_mapping(PMSM_MAP), **PMSM_UNITS)
    out.append(("PMSM profile 46", log.runs(log.actuators[0])))
    fx = PlantEffects.from_names("sensor_noise,quantisation,speed_losses")
    plant = simulate_profile("random", 7200.0, 1.0, list(CASE_NAMES), list(CASE_SPECS), fx, seed=0,
                             network=NETWORKS["first_order"]).log
    out.append(("plant: speed losses", plant.runs("knee")))
    return out


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--starts", type=int, default=6)
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args(argv)
    rng = np.random.default_rng(0)
    rows = []
    for name, runs in logs():
        d = diagnose(runs, quiet=True, stability=None)
        for cand in [c for c in d.candidates if c.refitted and c.report is not None]:
            fitted = dict(cand.report.model.params)
            ends = [cand.rmse_K]
            for _ in range(args.starts):
                start = {k: v * float(np.exp(rng.uniform(np.log(1 / 3), np.log(3)))) for k, v in fitted.items()}
                again = Candidate(cand.effect, cand.model, kind=cand.kind, replaces=cand.replaces,
                                  also_drops=cand.also_drops, channel=cand.channel, channel_unit=cand.channel_unit,
                                  formula=cand.formula, starts=cand.starts)
                again = refit_candidate(again, runs, Scheme(), d.base, d.base_bic, start)
                if again.rmse_K is not None:
                    ends.append(again.rmse_K)
            spread = (max(ends) - min(ends)) / min(ends)
            rows.append({"log": name, "change": cand.label, "rmse_K": ends, "spread": spread})
            print(f"{name:22s} {cand.label:40s} {min(ends):.4f}-{max(ends):.4f} K over {len(ends)} refits: "
                  f"spread {100 * spread:.2f} %", flush=True)
    within = sum(r["spread"] <= 0.01 for r in rows)
    print(f"{within} of {len(rows)} changes end within 1 % over their starts")
    if args.json:
        print(json.dumps({"rows": rows}))
    return {"rows": rows}


if __name__ == "__main__":
    main()
