"""Diagnosis of one actuator of a 3-actuator x 2 h log at 10 Hz, all candidates, with their refits.

Times the base fit, the quick score tests of every candidate and the refits,
and prints the ratio refits / quick scores (how much the score test saves
per candidate); then the whole diagnosis (every candidate refitted, and the
default), and the stepwise search (``--auto``) from the default start.  The
log hides speed losses; the hidden effect, once added, should bring
validation RMSE to the sensor noise (about 0.06 K here).

With ``--large``, also ``thermolimb diagnose --actuator hip`` on a 6 M-row Parquet
(three actuators of 2 M rows at 10 Hz, ``benchmarks/large_logs.py``'s log) in its
own process: its wall time and peak resident memory (target: 15 s, 1 GB).

With ``--against DIR`` (a worktree of an earlier commit: ``git worktree add ../before COMMIT``), the command
line's diagnoses, each in its own process, by this code and by DIR's in the same run: ``diagnose --auto`` on the
README tour's log and on the bundled UR3 joint, and with ``--large`` ``diagnose --actuator knee`` on the 6 M-row
Parquet of the plant's log that hides speed losses (so that the checks run).  For each: wall time, peak resident
memory, the ratio, and whether the verdicts (the model recommended, the walk's steps) are the same; and this
code's time with ``--stability 0`` (what the stability check adds to the walk it checks).  ``--repeat K`` runs each
of the three K times, alternated, and gives the medians (with the fastest and slowest beside them): this machine's
speed drifts by a quarter from one minute to the next, and one run of each can put a ratio anywhere in that band.

    python benchmarks/diagnose.py [--json] [--large] [--against DIR [--repeat K]]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from thermolimb.identification import FreeRunLeastSquares, IdentifiabilityError
from thermolimb.identification.thinning import thinned
from thermolimb.model import DEFAULT_MODEL
from thermolimb.plant import NETWORKS, PlantEffects, simulate_profile
from thermolimb.plant.cases import CASE_NAMES, CASE_SPECS
from thermolimb.workbench.diagnosis import auto_diagnose, diagnose
from thermolimb.workbench.diagnosis.candidates import candidate_models, score_candidate
from thermolimb.workbench.validation import fit_and_validate


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", action="store_true", help="print the result record last, on one line")
    parser.add_argument("--large", action="store_true", help="also diagnose one actuator of a 6 M-row Parquet")
    parser.add_argument("--against", metavar="DIR", help="also time the command line's diagnoses against the "
                        "checkout in DIR (an earlier commit's worktree), in the same run")
    parser.add_argument("--repeat", type=int, default=1, metavar="K", help="with --against: run each case K times, "
                        "alternated, and give the medians")
    args = parser.parse_args(argv)
    if args.repeat < 1:
        parser.error(f"--repeat takes a whole number of at least 1, got {args.repeat}")
    if args.against:
        record = {"against": against(args.against, args.large, args.repeat)}
        if args.json:
            print(json.dumps(record))
        return record

    fx = PlantEffects.from_names("sensor_noise,quantisation,speed_losses")
    start = time.perf_counter()
    log = simulate_profile("random", 2 * 3600.0, 0.1, list(CASE_NAMES), list(CASE_SPECS), fx,
                           seed=0, network=NETWORKS["first_order"]).log
    print(f"plant log: 3 actuators x {log.series('knee').n} samples in {time.perf_counter() - start:.1f} s")
    series = [log.series("knee")]

    start = time.perf_counter()
    base = fit_and_validate(series, DEFAULT_MODEL, estimator=FreeRunLeastSquares())
    t_base = time.perf_counter() - start
    train = list(base.train_series)
    candidates = [c for c in candidate_models(base.model.terms, series[0]) if c.kind == "add"]
    start = time.perf_counter()
    stride = base.estimator.stride_
    candidates = [score_candidate(cand, base.model, train, base.estimator.jacobian_,
                                  thinned(base.train_residual_K, train, stride), stride) for cand in candidates]
    t_scores = time.perf_counter() - start
    start = time.perf_counter()
    for cand in candidates:
        try:
            fit_and_validate(series, cand.model)
        except IdentifiabilityError:
            pass  # e.g. current^2 exactly proportional to effort^2 in this log: diagnose reports it too
    t_refits = time.perf_counter() - start

    start = time.perf_counter()
    d = diagnose(series, refit="all")
    t_all = time.perf_counter() - start
    start = time.perf_counter()
    d_strong = diagnose(series)
    t_strong = time.perf_counter() - start
    start = time.perf_counter()
    first, _ = auto_diagnose(series)
    t_auto = time.perf_counter() - start

    print(f"base fit                         {t_base:7.2f} s")
    print(f"quick scores, {len(candidates)} candidates        {t_scores:7.2f} s")
    print(f"refits, {len(candidates)} candidates              {t_refits:7.2f} s   ratio refits / scores "
          f"{t_refits / t_scores:5.1f} x")
    print(f"diagnose, every candidate refitted {t_all:6.2f} s   (target < 10 s)")
    print(f"diagnose, strong candidates only   {t_strong:6.2f} s")
    walk = "  ->  ".join(f"{step.get('change', 'start')} {step['rmse_K']:.3f} K" for step in first.auto)
    print(f"diagnose --auto from the default   {t_auto:6.2f} s   {walk}")
    print(f"recommended: {d.recommended.effect if d.recommended else None}; validation RMSE "
          f"{d.base.validation['rmse_K']:.3f} K -> {d.recommended.rmse_K:.3f} K (sensor noise 0.05 K, 0.1 degC steps)"
          if d.recommended else "recommended: none")
    record = {"samples": series[0].n, "base_s": t_base, "scores_s": t_scores, "refits_s": t_refits,
              "ratio": t_refits / t_scores, "diagnose_all_s": t_all, "diagnose_strong_s": t_strong,
              "auto_s": t_auto, "auto_steps": [step.get("change", "start") for step in first.auto],
              "recommended": d_strong.recommended.effect if d_strong.recommended else None,
              "rmse_after_K": d.recommended.rmse_K if d.recommended else None}
    if args.large:
        record["large"] = large = _large_parquet()
        print(f"{large['command']} ({large['rows']} rows): {large['seconds']:.1f} s (target 15 s), peak "
              f"{large['peak_MB']:.0f} MB (target 1000 MB), exit {large['exit']}")
    if args.json:
        print(json.dumps(record))
    return record


def _large_parquet() -> dict:
    import tempfile
    from pathlib import Path

    from large_logs import NAMES, measure, write_files

    rows = 2_000_000
    with tempfile.TemporaryDirectory() as tmp:
        write_files(Path(tmp), rows, ("parquet",))
        record = measure(["diagnose", "large.parquet", "--actuator", "hip", "--quiet"], Path(tmp))
    return {**record, "rows": rows * len(NAMES)}


UR3 = Path(__file__).resolve().parent.parent / "thermolimb" / "data" / "real" / "ur3-cobotops" / "dataset_02052023.csv"


def _diagnose(argv: list[str], cwd: Path, code: str | None) -> dict:
    """One ``thermolimb diagnose ... --json`` in its own process (by the checkout ``code``, else this one): wall
    time, peak resident memory, the recommended model and the walk's steps."""
    env = {**os.environ, **({"PYTHONPATH": str(Path(code).resolve()), "PYTHONSAFEPATH": "1"} if code else {})}
    out_path, err_path = cwd / "diagnose.out", cwd / "diagnose.err"
    start = time.perf_counter()
    with open(out_path, "wb") as out_file, open(err_path, "wb") as err_file:
        proc = subprocess.Popen([sys.executable, "-m", "thermolimb.cli.main", "diagnose", *argv, "--quiet", "--json"],
                                cwd=cwd, env=env, stdout=out_file, stderr=err_file)
        _, status, usage = os.wait4(proc.pid, 0)
        proc.returncode = os.waitstatus_to_exitcode(status)
    seconds = time.perf_counter() - start
    out, err = out_path.read_bytes(), err_path.read_bytes()
    try:
        result = json.loads(out)
        result = result[0] if isinstance(result, list) else result
        verdict = {"model": result.get("recommended_model"),
                   "walk": [step.get("change") for step in result.get("auto") or []]}
    except ValueError:
        verdict = {"error": err.decode().strip().splitlines()[-1:]}
    return {"seconds": round(seconds, 2), "peak_MB": round(usage.ru_maxrss / 1024.0), **verdict}


def against(code: str, large: bool, repeat: int = 1) -> list[dict]:
    """This code's diagnoses and ``code``'s, case by case, in one run, each ``repeat`` times alternated (module
    docstring)."""
    with tempfile.TemporaryDirectory() as tmp:
        d = Path(tmp)
        cli = [sys.executable, "-m", "thermolimb.cli.main", "simulate", "--profile", "random", "--network",
               "first_order", "--effects", "sensor_noise,quantisation,speed_losses", "--quiet"]
        subprocess.run([*cli, "--duration", "3600", "--dt", "1", "--out", "run.csv"], cwd=d, check=True)
        cases = [("README tour log, knee, --auto", ["run.csv", "--actuator", "knee", "--auto"]),
                 ("UR3 J5 (bundled), --auto", [str(UR3), "--drop-incomplete", "--map", "time=Timestamp,"
                  "effort=Current_J{j},temperature=Temperature_*{j},velocity=Speed_J{j}", "--actuator", "J5",
                  "--auto"])]
        if large:
            subprocess.run([*cli, "--duration", "200000", "--dt", "0.1", "--out", "large.parquet"], cwd=d, check=True)
            cases.append(("6 M-row Parquet hiding speed losses, knee", ["large.parquet", "--actuator", "knee"]))
        rows = []
        for name, argv in cases:
            runs = {"now": [], "before": [], "unchecked": []}
            for _ in range(repeat):
                # each child's peak is its own: wait4 on a fresh process, this one holding no large frame
                runs["now"].append(_diagnose(argv, d, None))
                runs["before"].append(_diagnose(argv, d, code))
                runs["unchecked"].append(_diagnose([*argv, "--stability", "0"], d, None))  # what the check adds
            now, before, unchecked = (_median(runs[k]) for k in ("now", "before", "unchecked"))
            rows.append({"case": name, "now": now, "before": before, "ratio": round(before["seconds"] /
                                                                                  now["seconds"], 2),
                         "same_verdict": len({_verdict(r) for r in runs["now"] + runs["before"]}) == 1,
                         "now_without_stability": unchecked,
                         "stability_adds": round(now["seconds"] / unchecked["seconds"] - 1.0, 2), "repeat": repeat})
            spread = (lambda r: f" ({r['fastest_s']:.1f}-{r['slowest_s']:.1f})") if repeat > 1 else (lambda r: "")
            print(f"{name:45s} now {now['seconds']:6.1f} s{spread(now)} {now['peak_MB']:5d} MB   {code}: "
                  f"{before['seconds']:6.1f} s{spread(before)} {before['peak_MB']:5d} MB   {rows[-1]['ratio']:.2f}x "
                  f"faster now   same verdict: {rows[-1]['same_verdict']} "
                  f"({' '.join(filter(None, now.get('walk', []))) or now.get('model')});   now with --stability 0: "
                  f"{unchecked['seconds']:.1f} s{spread(unchecked)} (the check adds "
                  f"{100 * rows[-1]['stability_adds']:.0f} %)")
    return rows


def _verdict(run: dict) -> str:
    return json.dumps({k: run.get(k) for k in ("model", "walk")})


def _median(runs: list[dict]) -> dict:
    """One case's runs by one code as one: the median time, with the fastest and the slowest, the largest peak,
    and the first run's verdict (every run's is compared in :func:`against`)."""
    seconds = sorted(r["seconds"] for r in runs)
    return {**runs[0], "seconds": round(float(np.median(seconds)), 2), "fastest_s": seconds[0],
            "slowest_s": seconds[-1], "peak_MB": max(r["peak_MB"] for r in runs)}


if __name__ == "__main__":
    main()
