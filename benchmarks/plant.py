"""The thermal plant's throughput and memory: actuator-steps per second, with and without protection's observer.

Each case runs ``thermolimb simulate``'s path (:func:`thermolimb.plant.run_profile`,
random holds and motions, three X8 actuators at 0.1 s, a realistic thermistor) in a
fresh process of its own, timed around the run alone; its peak resident memory is
that process's.  Each estimator runs stepped one interval at a time and in blocks
between protection's decisions (``run_profile(in_blocks=...)``, the same run to
rounding).  The papers have no plant, so the ratio printed is against protection on
the thermistor stepped one interval at a time (the least work per step), measured in
the same run.

    python benchmarks/plant.py [--duration-s 2000] [--repeats 3] [--json]
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys

CASES = {"thermistor, one interval at a time": ("measured", False),
         "thermistor, in blocks": ("measured", True),
         "observer, one interval at a time": ("observer", False),
         "observer, in blocks": ("observer", True)}

WORKER = """
import json, resource, sys, time
from thermolimb.plant import PlantEffects, ThermalPlant, ThermalProtection, run_profile
from thermolimb.plant.cases import CASE_NAMES, CASE_SPECS
from thermolimb.plant.profiles import PROFILES
import numpy as np
duration, estimator, in_blocks = float(sys.argv[1]), sys.argv[2], sys.argv[3] == "blocks"
rng = np.random.default_rng(0)
profile = PROFILES["random"](duration, 0.1, len(CASE_NAMES), rng)
protection = ThermalProtection(estimator=estimator)
plant = ThermalPlant(list(CASE_NAMES), list(CASE_SPECS), PlantEffects.realistic_sensor(), rng=rng,
                     protection=protection)
start = time.perf_counter()
run_profile(plant, profile, in_blocks=in_blocks)
wall = time.perf_counter() - start
print(json.dumps({"steps": int(profile.time_s.size), "actuators": len(CASE_NAMES), "wall_s": wall,
                  "peak_rss_MB": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0}))
"""


def measure(duration_s: float, estimator: str, in_blocks: bool) -> dict:
    out = subprocess.run([sys.executable, "-c", WORKER, str(duration_s), estimator, "blocks" if in_blocks else "steps"],
                         capture_output=True, text=True, check=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration-s", type=float, default=2000.0, help="simulated time per case (s), at 0.1 s")
    parser.add_argument("--repeats", type=int, default=3, help="runs per case; the fastest is kept")
    parser.add_argument("--json", action="store_true", help="print the record last, on one line")
    args = parser.parse_args(argv)
    record = {"duration_s": args.duration_s, "cases": {}}
    for label, (estimator, in_blocks) in CASES.items():
        runs = [measure(args.duration_s, estimator, in_blocks) for _ in range(args.repeats)]
        best = min(runs, key=lambda r: r["wall_s"])
        rate = best["steps"] * best["actuators"] / best["wall_s"]
        record["cases"][label] = {"actuator_steps_per_s": rate, "wall_s": best["wall_s"],
                                  "peak_rss_MB": max(r["peak_rss_MB"] for r in runs), "steps": best["steps"]}
    base = record["cases"]["thermistor, one interval at a time"]["actuator_steps_per_s"]
    for label, row in record["cases"].items():
        print(f"{label:34s} {row['actuator_steps_per_s']:9.0f} actuator-steps/s ({row['actuator_steps_per_s'] / base:5.2f}x "
              f"the thermistor's one at a time), {row['steps']} steps x 3 actuators, peak memory "
              f"{row['peak_rss_MB']:.0f} MB (fastest of {args.repeats})")
    print("target: >= 100000 actuator-steps/s with the observer")
    if args.json:
        print(json.dumps(record))
    return record


if __name__ == "__main__":
    main()
