"""What ``diagnose --auto --discover`` finds on plant logs whose missing effect no catalog term has.

Every log is a plant run (random profile, 2 h at 1 Hz, 0.05 K sensor noise,
0.1 degC steps), the knee diagnosed from the default start (``joule,effort_bias``):

* field weakening with no current logged: the heat grows with speed above a
  base speed, which no catalog term has; the discovery's validation RMSE is
  compared with the true law refitted (``current_heating`` on the same log
  with its current column, which is exactly the plant's heat);
* heat or cooling riding on a logged channel the model does not read: a fan's
  duty changing the conductance (``fan [%]``), a holding brake's coil
  (``brake [1]``), a driver board conducting into the winding (``driver [degC]``);
* a fan on the housing: the same fan on the two-node (``second_order``) and three-node (``x8``) networks, where it
  multiplies the outer mass's conductance, not the winding's; the walk must take the channel's form on a slow mass,
  and its final model, refitted on the whole log, is judged on the next seed's run (another fan schedule and duty);
* decoys: channels that vary and do nothing (``supply [V]``, ``led [1]``),
  alone and beside a catalog effect (speed losses): nothing generated may be taken;
* the catalog cases of ``benchmarks/hidden_effects.py`` (three-node X8 network)
  with ``--discover`` on: each must keep its result;
* the cost: ``diagnose --auto`` with and without ``--discover`` on the log of
  ``benchmarks/diagnose.py`` (2 h at 10 Hz, speed losses hidden).

The field-weakening and channel cases run on the one-mass network
(``first_order``): there the truth is the model's structure plus the one
effect, so they show that the right form is found (selection); the catalog
cases on the three-node network show that opening the vocabulary does not
disturb the catalog's search on data richer than the model.

    python benchmarks/discovery.py [--seeds 0] [--skip-catalog] [--json]
"""

from __future__ import annotations

import argparse
import json
import time

from thermolimb.logs import from_frame
from thermolimb.model import DEFAULT_MODEL
from thermolimb.model.terms import TERMS
from thermolimb.plant import NETWORKS, PlantEffects, simulate_profile
from thermolimb.plant.cases import CASE_NAMES, CASE_SPECS, HIDDEN_CASES
from thermolimb.workbench.diagnosis import auto_diagnose
from thermolimb.workbench.diagnosis.stability import Stability
from thermolimb.workbench.validation import Scheme, fit_and_validate, validate_model

CHANNEL_CASES = {"fan_cooling": "fan", "holding_brake": "brake", "driver_conduction": "driver"}
FAN_NETWORKS = ("second_order", "x8")
DECOY_CASES = {"decoys": "decoy_channels", "decoys_with_speed_losses": "decoy_channels,speed_losses"}


def plant_log(effects: str, seed: int, duration_s: float = 2 * 3600.0, dt_s: float = 1.0, network="first_order"):
    fx = PlantEffects.from_names(f"sensor_noise,quantisation,{effects}")
    return simulate_profile("random", duration_s, dt_s, list(CASE_NAMES), list(CASE_SPECS), fx, seed=seed,
                            network=NETWORKS[network]).log


def generated_in(model) -> list[str]:
    return [t for t in model if TERMS[t].generated]


def walk(series, discover: bool) -> tuple[dict, float]:
    start = time.perf_counter()
    first, steps = auto_diagnose(series, discover=discover, stability=STABILITY[0])
    seconds = time.perf_counter() - start
    return {"rmse_K": first.auto[-1]["rmse_K"], "base_K": first.auto[0]["rmse_K"], "model": list(steps[-1].model),
            "walk": [s.get("change", "start") for s in first.auto],
            "proposals": [d.proposal.formula for d in steps if d.proposal is not None]}, seconds


def field_weakening(seed: int) -> dict:
    log = plant_log("field_weakening", seed)
    series = [from_frame(log.frame.drop(columns="current")).series("knee")]
    catalog, _ = walk(series, False)
    found, seconds = walk(series, True)
    truth = fit_and_validate([log.series("knee")], "current_heating").validation["rmse_K"]
    names_speed = any("velocity" in TERMS[t].columns for t in generated_in(found["model"]))
    return {"case": "field_weakening (no current)", "seed": seed, "base_K": found["base_K"],
            "catalog_K": catalog["rmse_K"], "discovery_K": found["rmse_K"], "truth_K": truth,
            "ratio_to_truth": found["rmse_K"] / truth, "names_velocity": names_speed,
            "passes": found["rmse_K"] <= 1.5 * truth and names_speed, "proposed": found["proposals"],
            "final": found["model"], "seconds": seconds}


def channel_case(effect: str, channel: str, seed: int) -> dict:
    series = [plant_log(effect, seed).series("knee")]
    catalog, _ = walk(series, False)
    found, seconds = walk(series, True)
    reads = [t for t in generated_in(found["model"]) if f"extra.{channel}" in TERMS[t].columns]
    ratio = found["rmse_K"] / found["base_K"]
    return {"case": f"{effect} ({channel})", "seed": seed, "base_K": found["base_K"], "catalog_K": catalog["rmse_K"],
            "discovery_K": found["rmse_K"], "ratio_to_base": ratio, "channel_terms": reads,
            "passes": bool(reads) and ratio <= 0.35, "proposed": found["proposals"], "final": found["model"],
            "seconds": seconds}


def housing_fan_case(network: str, seed: int) -> dict:
    series = [plant_log("fan_cooling", seed, network=network).series("knee")]
    catalog, _ = walk(series, False)
    found, seconds = walk(series, True)
    on_mass = [t for t in generated_in(found["model"]) if TERMS[t].airflow_on and "extra.fan" in TERMS[t].columns]
    ratio = found["rmse_K"] / found["base_K"]
    following = [plant_log("fan_cooling", seed + 1, network=network).series("knee")]
    carried = {label: validate_model(series, model, Scheme.on_runs(following)).validation["rmse_K"]
               for label, model in (("default", DEFAULT_MODEL), ("found", tuple(found["model"])))}
    return {"case": f"fan on the housing ({network})", "seed": seed, "base_K": found["base_K"],
            "catalog_K": catalog["rmse_K"], "discovery_K": found["rmse_K"], "ratio_to_base": ratio,
            "channel_terms": on_mass, "next_run_K": carried, "passes": bool(on_mass) and ratio <= 0.35
            and carried["found"] <= 0.35 * carried["default"], "proposed": found["proposals"],
            "final": found["model"], "seconds": seconds}


def decoy_case(name: str, effects: str, seed: int) -> dict:
    series = [plant_log(effects, seed).series("knee")]
    catalog, _ = walk(series, False)
    found, seconds = walk(series, True)
    taken = generated_in(found["model"])
    return {"case": name, "seed": seed, "base_K": found["base_K"], "catalog_K": catalog["rmse_K"],
            "discovery_K": found["rmse_K"], "generated_taken": taken, "passes": not taken,
            "proposed": found["proposals"], "final": found["model"], "seconds": seconds}


def catalog_case(name: str, seed: int) -> dict:
    case = HIDDEN_CASES[name]
    series = [case.log(seed).series("knee")]
    without, t_without = walk(series, False)
    with_discovery, t_with = walk(series, True)
    found_without, found_with = case.found_in(without["model"]), case.found_in(with_discovery["model"])
    return {"case": f"catalog: {name}", "seed": seed, "base_K": without["base_K"], "catalog_K": without["rmse_K"],
            "discovery_K": with_discovery["rmse_K"], "found_without": found_without, "found_with": found_with,
            "generated_taken": generated_in(with_discovery["model"]), "passes": found_with == found_without,
            "proposed": with_discovery["proposals"], "final": with_discovery["model"],
            "seconds": t_with, "seconds_without": t_without}


def cost() -> dict:
    fx = PlantEffects.from_names("sensor_noise,quantisation,speed_losses")
    log = simulate_profile("random", 2 * 3600.0, 0.1, list(CASE_NAMES), list(CASE_SPECS), fx, seed=0,
                           network=NETWORKS["first_order"]).log
    series = [log.series("knee")]
    _, without = walk(series, False)
    _, with_discovery = walk(series, True)
    return {"samples": series[0].n, "auto_s": without, "auto_discover_s": with_discovery,
            "ratio": with_discovery / without}


# the stability check every walk makes (--stability K replicates, as thermolimb diagnose; 0: off)
STABILITY: list = [None]


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, nargs="+", default=[0])
    parser.add_argument("--skip-catalog", action="store_true", help="leave out the ten three-node catalog cases")
    parser.add_argument("--json", action="store_true", help="print the result record last, on one line")
    parser.add_argument("--stability", type=int, default=10, metavar="K",
                        help="replicates of the stability check, as thermolimb diagnose's default (0: off)")
    args = parser.parse_args(argv)
    STABILITY[0] = Stability(args.stability) if args.stability else None
    rows = []
    for seed in args.seeds:
        rows.append(field_weakening(seed))
        rows += [channel_case(effect, channel, seed) for effect, channel in CHANNEL_CASES.items()]
        rows += [housing_fan_case(network, seed) for network in FAN_NETWORKS]
        rows += [decoy_case(name, effects, seed) for name, effects in DECOY_CASES.items()]
        if not args.skip_catalog:
            rows += [catalog_case(name, seed) for name in HIDDEN_CASES]
    timing = cost()
    print(f"{'case':34s} {'seed':>4s} {'base K':>7s} {'catalog K':>9s} {'discover K':>10s} {'pass':>5s} {'s':>6s}  "
          f"proposed / final model")
    for r in rows:
        print(f"{r['case']:34s} {r['seed']:4d} {r['base_K']:7.3f} {r['catalog_K']:9.3f} {r['discovery_K']:10.3f} "
              f"{str(r['passes']):>5s} {r['seconds']:6.1f}  {'; '.join(r['proposed']) or '-'} / {','.join(r['final'])}")
    for r in rows:
        if "next_run_K" in r:
            carried = r["next_run_K"]
            print(f"{r['case']}, seed {r['seed']}: fitted on this run, on seed {r['seed'] + 1}'s run "
                  f"{carried['found']:.3f} K against Jorgensen et al.'s model's {carried['default']:.3f} K")
    fw = [r for r in rows if r["case"].startswith("field")]
    for r in fw:
        print(f"field weakening, seed {r['seed']}: discovery {r['discovery_K']:.3f} K vs the true law refitted "
              f"{r['truth_K']:.3f} K: ratio {r['ratio_to_truth']:.2f} (target <= 1.5)")
    print(f"passed {sum(r['passes'] for r in rows)} of {len(rows)}")
    print(f"cost on the benchmarks/diagnose.py log ({timing['samples']} samples): --auto {timing['auto_s']:.1f} s, "
          f"--auto --discover {timing['auto_discover_s']:.1f} s, ratio {timing['ratio']:.2f} (target <= 2)")
    record = {"cases": rows, "cost": timing}
    if args.json:
        print(json.dumps(record))
    return record


if __name__ == "__main__":
    main()
