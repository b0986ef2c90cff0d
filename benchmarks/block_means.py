"""How far a long log's block means take a free run from the full rate's, and what they save.

A fit of a log of more than 100,000 compared samples simulates it on blocks of ``k`` samples, each term's
contribution averaged over its block (``thermolimb/model/block_means.py``).  This benchmark simulates the plant's
random profile at 10 Hz with speed losses (the 6 M-row Parquet's kind of log, shorter: how far blocks miss depends
on the block and the time constant, not on the log's length) and, for the knee and the model that explains it
(``joule,effort_bias,speed_losses``, its values fitted once at the full rate), prints at RC = 83 s (the fit's), 30 s
and 15 s: the free run on blocks of 15 samples (1.5 s, the knee's stride on the Parquet) and on every 15th sample
held until the next, each against the full rate's at the blocks' starts (rms and largest, K), and the time of one
free run of each (best of five, one process).

    python benchmarks/block_means.py [--json]
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

from thermolimb.identification import FreeRunLeastSquares
from thermolimb.identification.thinning import on_blocks
from thermolimb.plant import NETWORKS, PlantEffects, simulate_profile
from thermolimb.plant.cases import CASE_NAMES, CASE_SPECS

MODEL = ("joule", "effort_bias", "speed_losses")
BLOCK = 15


def best_of(fn, repeat: int = 5) -> float:
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return min(times)


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", action="store_true", help="print the result record last, on one line")
    args = parser.parse_args(argv)
    fx = PlantEffects.from_names("sensor_noise,quantisation,speed_losses")
    log = simulate_profile("random", 20000.0, 0.1, list(CASE_NAMES), list(CASE_SPECS), fx, seed=0,
                           network=NETWORKS["first_order"]).log
    series = log.series("knee")
    fitted = FreeRunLeastSquares(model=MODEL).fit(series).model_
    shown, _ = on_blocks(series, np.arange(0, series.n, BLOCK), BLOCK)
    kept = series.slice(0, series.n, BLOCK)
    rate = series.rate_K_per_s()
    print(f"knee: {series.n} samples at 0.1 s; blocks of {BLOCK} ({BLOCK * 0.1:.1f} s); fitted RC_s = "
          f"{fitted.params['RC_s']:.1f} s")
    rows = []
    for rc in (fitted.params["RC_s"], 30.0, 15.0):
        model = fitted.with_params({**fitted.params, "RC_s": rc})
        full = model.free_run(series, rate)[::BLOCK]
        row = {"RC_s": round(rc, 1), "full_ms": 1e3 * best_of(lambda: model.free_run(series, rate)),
               "blocks_ms": 1e3 * best_of(lambda: model.free_run(shown, rate))}
        for name, part in (("blocks", shown), ("kept", kept)):
            miss = model.free_run(part, rate) - full
            row[f"{name}_rms_K"] = float(np.sqrt(np.mean(miss ** 2)))
            row[f"{name}_max_K"] = float(np.abs(miss).max())
        rows.append(row)
        print(f"RC {rc:6.1f} s: blocks miss {row['blocks_rms_K']:.4f} K rms, {row['blocks_max_K']:.3f} K at most; "
              f"kept samples {row['kept_rms_K']:.3f} K rms, {row['kept_max_K']:.2f} K at most; one free run "
              f"{row['full_ms']:.1f} ms at the full rate, {row['blocks_ms']:.2f} ms on blocks")
    record = {"samples": series.n, "block": BLOCK, "rows": rows}
    if args.json:
        print(json.dumps(record))
    return record


if __name__ == "__main__":
    main()
