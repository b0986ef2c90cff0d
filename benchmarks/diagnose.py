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

    python benchmarks/diagnose.py [--json] [--large]
"""

from __future__ import annotations

import argparse
import json
import time

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
    args = parser.parse_args(argv)

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
    for cand in candidates:
        stride = base.estimator.stride_
        score_candidate(cand, base.model, train, base.estimator.jacobian_,
                        thinned(base.train_residual_K, train, stride), stride)
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


if __name__ == "__main__":
    main()
