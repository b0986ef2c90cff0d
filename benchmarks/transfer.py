"""Does the model a walk finds carry over?  Fitted on one run of a joint, predicting its other runs.

For every bundled real source with several runs of one actuator -- the UR3's six joints (two parts of one
log, 5.2 h apart), the WidowX-200 waist (two 600 s runs), the BLDC bench (two heating runs of the winding), the
PMSM bench (profiles 24 and 46, their coolant 72 K apart: the offset of a model that does not read it follows
each held-out run's, Jorgensen et al. Eq. 5) -- and for plant logs richer than the model (the X8's three masses
with speed losses and copper's tempco hidden; four duty cycles of one joint), each run in turn is the one fitted on:

* **default**: Jorgensen et al.'s model fitted on that run, validated on the others
  (``thermolimb fit RUN --validate-on OTHERS``);
* **walk**: the model ``thermolimb diagnose RUN --auto`` walks to on that run, fitted and validated the same way.

The table gives both held-out errors, the walk's steps and their ratio; a case counts as *better* when the
walk's model is at least 10 % better on the other runs, *worse* when it is more than 5 % worse.  Part two,
``--loro``: where a source has three runs or more (the plant's duty cycles), ``diagnose`` is given all runs but
one (its default scheme) and its model judged on the one left out, against the default model fitted on the
same runs.

``--plant NETWORK:EFFECTS`` builds the plant's four runs on another network and with other hidden effects (the
default, ``x8:speed_losses,winding_tempco``, is the table's), to try the walk on plants it was not tuned on.
``--step-K 1`` reads the plant's thermistor in whole degrees, as many servos report it.
``--sources pmsm-sensors``: the PMSM's two profiles read at its other sensors (the stator's tooth and yoke
thermocouples, the magnet's telemetry), on which nothing in the walk was tuned.
``--sources step``: plain bench step tests on that plant (:func:`thermolimb.plant.duties.step_test`: 18 min held
at 1.5, 2.0 and 2.5 times the continuous effort, then released, at 2 Hz, and one at 2.0 that starts warm), the
kind of log a lab writes first and the one with the least to tell a model.

Everything goes through the command line, so that ``--code DIR`` measures another checkout of the suite (a git
worktree of an earlier commit) on the same runs (written once, by this checkout), in the same process tree: the
transfer table and the walk's time before and after a change, side by side.

Each run's effort is also said by how much of the offset's constant and of the effort bias's input it moves apart
from each other and Joule heating's (under a share of 0.1 for the bias, not the offset, a fit sets the bias aside);
``--shares`` prints those alone.

    python benchmarks/transfer.py [--json] [--sources ur3,wx200,bldc,pmsm,plant,step,pmsm-sensors] [--code DIR] [--loro]
                                  [--plant NETWORK:EFFECTS] [--step-K K] [--shares]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
BETTER, WORSE = 0.10, 0.05  # at least 10 % better; more than 5 % worse


PLANT = "x8:speed_losses,winding_tempco"
SOURCES = ("ur3", "wx200", "bldc", "pmsm", "plant", "step", "pmsm-sensors")
PMSM_SENSORS = ("stator_tooth", "stator_yoke", "pm")  # the PMSM's other thermocouples and its magnet's telemetry
STEPS = ((1.5, 0, 0.0), (2.0, 1, 0.0), (2.5, 2, 0.0), (2.0, 3, 600.0))  # load (x continuous), seed, warm-up s


def write_runs(folder: Path, sources: list[str], plant: str = PLANT, step_K: float = 0.1) -> dict[str, dict]:
    """Each source's runs as canonical CSV files, one per run (all of the log's actuators in each, so that a
    model with the neighbours' heat has them): ``{source: {"actuators": [...], "runs": [paths]}}``."""
    from thermolimb.data import PMSM_MAP, PMSM_UNITS, REAL_LOGS, pmsm_profile
    from thermolimb.logs import from_frame, parse_mapping, read_log
    from thermolimb.plant import NETWORKS, PlantEffects, simulate_profile
    from thermolimb.plant.cases import CASE_NAMES, CASE_SPECS
    from thermolimb.plant.duties import step_test

    def save(log, name: str) -> Path:
        path = folder / f"{name}.csv"
        log.write(path)
        return path

    out = {}
    if "ur3" in sources:
        log = REAL_LOGS["ur3"].read()[0]
        first = log.runs(log.actuators[0])
        cut = 0.5 * (first[0].time_s[-1] + first[1].time_s[0])  # between the two parts
        frame = log.frame
        parts = [frame[frame["time"] < cut], frame[frame["time"] > cut]]
        runs = [save(from_frame(p.reset_index(drop=True), source=f"ur3 part {k + 1}"), f"ur3_part{k + 1}")
                for k, p in enumerate(parts)]
        out["ur3"] = {"actuators": list(log.actuators), "runs": runs}
    if "wx200" in sources:
        logs = REAL_LOGS["wx200"].read()
        out["wx200"] = {"actuators": ["waist"], "runs": [save(log, Path(log.source).stem) for log in logs]}
    if "bldc" in sources:
        logs = REAL_LOGS["bldc"].read()
        out["bldc"] = {"actuators": ["bldc"], "runs": [save(log, Path(log.source).stem) for log in logs]}
    for sensor in ["stator_winding"] * ("pmsm" in sources) + list(PMSM_SENSORS) * ("pmsm-sensors" in sources):
        mapping = parse_mapping(PMSM_MAP.replace("temperature=stator_winding", f"temperature={sensor}"))
        logs = [read_log(pmsm_profile(k), mapping=mapping, actuator_name="pmsm", **PMSM_UNITS) for k in (24, 46)]
        name = "pmsm" if sensor == "stator_winding" else f"pmsm_{sensor}"
        out[name] = {"actuators": ["pmsm"], "runs": [save(log, f"{name}_profile{k}") for log, k in zip(logs, (24, 46))]}
    network, _, hidden = plant.partition(":")  # the plant of the plant's duties and of its step tests
    fx = PlantEffects.from_names(f"sensor_noise,quantisation,{hidden}")
    fx = fx.replace(quantisation=replace(fx.quantisation, step_K=step_K))  # the thermistor's steps
    if "plant" in sources:
        duties = [("random", 0), ("random", 1), ("walking", 2), ("squat", 3)]
        runs = [save(simulate_profile(profile, 7200.0, 1.0, list(CASE_NAMES), list(CASE_SPECS), fx, seed=seed,
                                      network=NETWORKS[network], load_scale=1.5).log, f"plant_{profile}{seed}")
                for profile, seed in duties]
        out["plant"] = {"actuators": ["knee"], "runs": runs}
    if "step" in sources:
        spec = replace(CASE_SPECS[0], network=NETWORKS[network])
        runs = [save(step_test(spec, fx, load, seed, warm_s), f"step{load:g}" + ("_warm" if warm_s else ""))
                for load, seed, warm_s in STEPS]
        out["step"] = {"actuators": ["knee"], "runs": runs}
    return out


def thermolimb(code: Path | None, *args: str) -> tuple[dict, float]:
    """The command line of the suite at ``code`` (this checkout by default): its JSON record and wall time."""
    env = dict(os.environ)
    if code is not None:
        env["PYTHONPATH"] = str(code)
    start = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "thermolimb.cli.main", *args, "--json", "--quiet"],
                          capture_output=True, text=True, env=env, cwd=code or ROOT)
    wall = time.perf_counter() - start
    if done.returncode != 0:
        return {"error": done.stderr.strip().splitlines()[-1] if done.stderr.strip() else f"exit {done.returncode}"}, wall
    return json.loads(done.stdout), wall


def one(record):
    return record[0] if isinstance(record, list) else record


def case(code, fit_on: list[Path], judged_on: list[Path], actuator: str) -> dict:
    """The default model and the walk's, each fitted on ``fit_on`` and validated on ``judged_on``."""
    fit_args = [str(p) for p in fit_on]
    walk, walk_s = thermolimb(code, "diagnose", *fit_args, "--actuator", actuator, "--auto")
    walk = one(walk)
    out = {"fit_on": [p.stem for p in fit_on], "judged_on": [p.stem for p in judged_on], "actuator": actuator,
           "walk_s": walk_s}
    if "error" in walk:
        out["error"] = walk["error"]
        return out
    final = walk["auto"][-1]["model"]
    out["steps"] = [s.get("change", "start") for s in walk["auto"]]
    out["final"] = final
    for key, model in (("default", None), ("walk", final)):
        extra = [] if model is None else ["--model", ",".join(model)]
        record, _ = thermolimb(code, "fit", *fit_args, "--actuator", actuator, *extra, "--validate-on",
                               *[str(p) for p in judged_on])
        record = one(record)
        out[f"{key}_K"] = record["validation"]["rmse_K"] if "validation" in record else None
        if "error" in record:
            out[f"{key}_error"] = record["error"]
    if out["default_K"] and out["walk_K"]:
        out["ratio"] = out["walk_K"] / out["default_K"]
        out["verdict"] = ("better" if out["ratio"] <= 1 - BETTER else "worse" if out["ratio"] > 1 + WORSE
                          else "same")
    return out


def own_shares(sources: dict) -> dict:
    """Per source, actuator and run, the shares of the offset's constant and of the effort bias's input their own
    beside each other and Joule heating's (:func:`thermolimb.workbench.excitation.own_shares`; the bias's under
    ``submodel.OWN_SHARE``, the offset's not, and a fit sets the bias aside), by this checkout's code."""
    from thermolimb.logs import read_log
    from thermolimb.workbench.excitation import own_shares as shares_of

    out = {}
    for name, source in sources.items():
        logs = [read_log(p) for p in source["runs"]]
        out[name] = {a: {Path(p).stem: {k: round(v, 3) for k, v in shares_of(log.runs(a), ["joule", "effort_bias"])
                                        .items() if k != "joule"} for p, log in zip(source["runs"], logs)}
                     for a in source["actuators"]}
        for a, shares in out[name].items():
            print(f"{name:17s} {a:6s} own shares (offset / bias): "
                  + ", ".join(f"{run} {v['T_offset_C']:.3f} / {v['effort_bias']:.3f}" for run, v in shares.items()))
    return out


def transfer(code, sources: dict, loro: bool) -> dict:
    rows = []
    for name, source in sources.items():
        runs = source["runs"]
        for actuator in source["actuators"]:
            for k, run in enumerate(runs):
                others = [r for j, r in enumerate(runs) if j != k]
                row = case(code, [run], others, actuator)
                rows.append({"source": name, "part": "one run to the others", **row})
                _print(rows[-1])
            if loro and len(runs) >= 3:
                for k, run in enumerate(runs):
                    row = case(code, [r for j, r in enumerate(runs) if j != k], [run], actuator)
                    rows.append({"source": name, "part": "all runs but one", **row})
                    _print(rows[-1])
    judged = [r for r in rows if "verdict" in r]
    summary = {part: {"cases": len(group), "better": sum(r["verdict"] == "better" for r in group),
                      "worse": sum(r["verdict"] == "worse" for r in group),
                      "walk_s_median": float(np.median([r["walk_s"] for r in group])) if group else None}
               for part in ("one run to the others", "all runs but one")
               for group in [[r for r in judged if r["part"] == part]] if group}
    for part, s in summary.items():
        print(f"{part}: the walk's model is at least {100 * BETTER:.0f} % better in {s['better']} of {s['cases']} "
              f"cases, more than {100 * WORSE:.0f} % worse in {s['worse']}; median walk {s['walk_s_median']:.1f} s")
    return {"rows": rows, "summary": summary, "own_shares": own_shares(sources)}


def _print(row: dict) -> None:
    if "error" in row:
        print(f"{row['source']:17s} {row['actuator']:6s} fit on {','.join(row['fit_on'])}: {row['error']}")
        return
    steps = " ".join(s for s in row["steps"][1:]) or "(no change)"

    def kelvin(key):
        return f"{row[key]:.3f} K" if row.get(key) is not None else f"failed ({row.get(key.replace('_K', '_error'))})"

    print(f"{row['source']:17s} {row['actuator']:6s} fit on {','.join(row['fit_on']):36s} default "
          f"{kelvin('default_K')}, walk {kelvin('walk_K')} ({row.get('ratio', float('nan')):.2f}x, "
          f"{row.get('verdict', '?')}): {steps}  [{row['walk_s']:.1f} s]")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sources", default="ur3,wx200,bldc,pmsm,plant",
                        help=f"comma-separated, of {', '.join(SOURCES)} (default ur3,wx200,bldc,pmsm,plant)")
    parser.add_argument("--code", type=Path, default=None, help="another checkout of the suite to measure")
    parser.add_argument("--loro", action="store_true", help="also diagnose all runs but one (sources of 3+ runs)")
    parser.add_argument("--plant", default=PLANT, metavar="NETWORK:EFFECTS",
                        help=f"the plant's network and hidden effects (default {PLANT})")
    parser.add_argument("--step-K", type=float, default=0.1, metavar="K",
                        help="the plant's thermistor reads in steps of this many K (default 0.1; 1 as servos "
                             "reporting whole degrees)")
    parser.add_argument("--shares", action="store_true",
                        help="only print each run's own shares of the offset and the bias (no walks)")
    parser.add_argument("--json", action="store_true", help="print the record last, on one line")
    args = parser.parse_args(argv)
    from thermolimb.plant import NETWORKS, PlantEffects
    unknown = [name for name in args.sources.split(",") if name not in SOURCES]
    if unknown:
        parser.error(f"--sources {args.sources!r}: {', '.join(map(repr, unknown))} is no source; expected some of "
                     f"{', '.join(SOURCES)}, separated by commas")
    network, _, hidden = args.plant.partition(":")
    if network not in NETWORKS:
        parser.error(f"--plant {args.plant!r}: the network must be one of {', '.join(NETWORKS)}, before a colon")
    if not (np.isfinite(args.step_K) and args.step_K > 0):
        parser.error(f"--step-K {args.step_K:g}: the thermistor's step must be a positive number of kelvin")
    try:
        PlantEffects.from_names(hidden)
    except ValueError as exc:
        parser.error(f"--plant {args.plant!r}: {exc}")
    with tempfile.TemporaryDirectory() as folder:
        sources = write_runs(Path(folder), args.sources.split(","), args.plant, args.step_K)
        record = {"own_shares": own_shares(sources)} if args.shares else transfer(args.code, sources, args.loro)
    if args.json:
        print(json.dumps(record))
    return record


if __name__ == "__main__":
    main()
