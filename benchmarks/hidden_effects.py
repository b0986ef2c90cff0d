"""What the stepwise search finds from the default start, on plant logs richer than the model.

Part 1: each case of ``thermolimb.plant.cases`` on the default three-node X8
network (2 h at 1 Hz, 0.05 K noise, 0.1 degC steps): the walk of
``diagnose --auto`` from ``joule,effort_bias``, whether the hidden effect's
term is in the final model, and validation RMSE before and after.
Part 2: bench step tests (8 min at 1 Hz, three load pulses) on a two-mass
plant: the final model's validation RMSE against the first-order model's,
both with hidden states carried from the start, and with the restart at the
split for comparison.
Part 3: the catalog search on a richer base: a two-node plant (winding and a
heavier housing, which the model has neither of), 1 h at 2 Hz of random holds
and motions, one effect at a time (an ambient swinging +-4 K and drifting 3 K/h,
copper tempco, motion cooling): is the effect found once the slow mass is taken?

    python benchmarks/hidden_effects.py [--seeds 0 1] [--json]
"""

from __future__ import annotations

import argparse
import json
import time

from thermolimb.plant import NETWORKS, X8_9, AmbientVariation, PlantEffects, simulate_profile
from thermolimb.plant.cases import CASE_NAMES, CASE_SPECS, HIDDEN_CASES
from thermolimb.workbench.diagnosis import auto_diagnose
from thermolimb.workbench.diagnosis.stability import Stability
from thermolimb.workbench.validation import fit_and_validate


def x8_cases(seed: int) -> list[dict]:
    rows = []
    for name, case in HIDDEN_CASES.items():
        start = time.perf_counter()
        first, steps = auto_diagnose([case.log(seed).series("knee")], stability=STABILITY[0])
        rows.append({"case": name, "term": case.term, "seed": seed, "found": case.found_in(steps[-1].model),
                     "before_K": first.auto[0]["rmse_K"], "after_K": first.auto[-1]["rmse_K"],
                     "walk": [s.get("change", "start") for s in first.auto], "final": list(steps[-1].model),
                     "seconds": time.perf_counter() - start})
    return rows


def step_tests(seeds) -> list[dict]:
    rows = []
    for seed in seeds:
        log = simulate_profile("pulses", 480.0, 1.0, list(CASE_NAMES[:2]), list(CASE_SPECS[:2]),
                               PlantEffects.from_names("sensor_noise,quantisation"), seed=seed,
                               network=NETWORKS["second_order"]).log
        series = [log.series("knee")]
        _, steps = auto_diagnose(series, stability=STABILITY[0])
        final = steps[-1].model
        first_order = fit_and_validate(series, "joule").validation["rmse_K"]
        restarted = fit_and_validate(series, final, restart_at_split=True).validation["rmse_K"]
        rows.append({"seed": seed, "final": list(final), "first_order_K": first_order,
                     "final_K": steps[-1].base.validation["rmse_K"], "final_restarted_K": restarted,
                     "ratio": steps[-1].base.validation["rmse_K"] / first_order})
    return rows


RICHER_BASE_EFFECTS = ("ambient_variation", "winding_tempco", "motion_cooling")
# the plant's airflow cools its housing: on a model with a slow mass, the term that says so acts on that mass
TERMS_OF = {"ambient_variation": ("ambient_variation",), "winding_tempco": ("winding_tempco",),
            "motion_cooling": ("motion_cooling", "housing_motion_cooling")}


def richer_base(seed: int) -> list[dict]:
    rows = []
    for effect in RICHER_BASE_EFFECTS:
        fx = PlantEffects.from_names(["sensor_noise", "quantisation", effect])
        if effect == "ambient_variation":
            fx = fx.replace(ambient_variation=AmbientVariation(amplitude_K=4.0, period_s=1500.0, drift_K_per_h=3.0))
        log = simulate_profile("random", 3600.0, 0.5, ["knee"], [X8_9], fx, seed=seed,
                               network=NETWORKS["second_order"]).log
        start = time.perf_counter()
        first, steps = auto_diagnose([log.series("knee")], stability=STABILITY[0])
        last = next((c for c in steps[-1].candidates if c.kind == "add" and c.effect in TERMS_OF[effect]), None)
        rows.append({"effect": effect, "seed": seed, "found": any(t in steps[-1].model for t in TERMS_OF[effect]),
                     "before_K": first.auto[0]["rmse_K"], "after_K": first.auto[-1]["rmse_K"],
                     "walk": [s.get("change", "start") for s in first.auto], "final": list(steps[-1].model),
                     "left_status": None if last is None else last.status,
                     "left_p_value": None if last is None else last.p_value,
                     "left_rmse_K": None if last is None else last.rmse_K,
                     "seconds": time.perf_counter() - start})
    return rows


# the stability check every walk makes (--stability K replicates, as thermolimb diagnose; 0: off)
STABILITY: list = [None]


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, nargs="+", default=[0, 1])
    parser.add_argument("--json", action="store_true", help="print the result record last, on one line")
    parser.add_argument("--stability", type=int, default=10, metavar="K",
                        help="replicates of the stability check, as thermolimb diagnose's default (0: off)")
    args = parser.parse_args(argv)
    STABILITY[0] = Stability(args.stability) if args.stability else None
    cases = [row for seed in args.seeds for row in x8_cases(seed)]
    print(f"{'case':18s} {'seed':>4s} {'found':>5s} {'before K':>9s} {'after K':>8s}  walk")
    for r in cases:
        print(f"{r['case']:18s} {r['seed']:4d} {str(r['found']):>5s} {r['before_K']:9.3f} {r['after_K']:8.3f}  "
              + " -> ".join(r["walk"][1:]))
    for seed in args.seeds:
        found = sum(r["found"] for r in cases if r["seed"] == seed)
        print(f"seed {seed}: hidden effect found in {found} of {len(HIDDEN_CASES)} cases")
    steps = step_tests(args.seeds)
    print(f"\n{'step test':10s} {'first-order K':>13s} {'final K':>8s} {'ratio':>6s} {'restarted K':>11s}  final model")
    for r in steps:
        print(f"seed {r['seed']:<5d} {r['first_order_K']:13.3f} {r['final_K']:8.3f} {r['ratio']:6.3f} "
              f"{r['final_restarted_K']:11.3f}  {','.join(r['final'])}")
    richer = [row for seed in args.seeds for row in richer_base(seed)]
    print(f"\n{'on a two-node base':18s} {'seed':>4s} {'found':>5s} {'before K':>9s} {'after K':>8s}  walk")
    for r in richer:
        left = "" if r["found"] or r["left_status"] is None else (
            f"  (left: {r['left_status']}, p = {r['left_p_value']:.2g}"
            + (f", refit {r['left_rmse_K']:.3f} K)" if r["left_rmse_K"] is not None else ")"))
        print(f"{r['effect']:18s} {r['seed']:4d} {str(r['found']):>5s} {r['before_K']:9.3f} {r['after_K']:8.3f}  "
              + " -> ".join(r["walk"][1:]) + left)
    record = {"x8_cases": cases, "step_tests": steps, "richer_base": richer}
    if args.json:
        print(json.dumps(record))
    return record


if __name__ == "__main__":
    main()
