"""Thermal protection on the measured thermistor against protection on the observer's winding estimate.

Part 1: the observer's tracking of the true winding on a plant richer than
its model (copper tempco, speed losses, drifting ambient, a lagging, noisy,
quantised thermistor; 1 h of random holds and motions at 1.5x the continuous
effort), against the thermistor's own error.
Part 2: a 10 h soak with every plant effect on at 3x the continuous effort:
the hottest true winding of each actuator under each protection, and the
limit.  Jorgensen et al.'s method has no protection of its own; the comparison is
the rig's two protections in the same run.

    python benchmarks/protection.py [--seeds 0 1] [--json]
"""

from __future__ import annotations

import argparse
import json
import time
from dataclasses import replace

import numpy as np

from thermolimb.plant import (
    PLANT_EFFECTS,
    X8_9,
    X8_16,
    PlantEffects,
    ThermalPlant,
    ThermalProtection,
    run_profile,
)
from thermolimb.plant.profiles import PROFILES

SPECS = (X8_9, X8_16, X8_9)


def drive(plant, profile, scale):
    """True, measured and estimated windings of a protected run (estimated: the measured one without observer)."""
    run = run_profile(plant, replace(profile, load=profile.load * scale))
    return run.true_winding_C, run.measured_C, run.estimated_C if run.estimated_C is not None else run.measured_C


def tracking(seed: int) -> dict:
    effects = PlantEffects.from_names("sensor_lag,sensor_noise,quantisation,winding_tempco,speed_losses,"
                                      "ambient_variation")
    rng = np.random.default_rng(seed)
    plant = ThermalPlant(["a", "b"], SPECS[:2], effects, rng=rng)
    true, measured, estimate = drive(plant, PROFILES["random"](3600.0, 1.0, 2, rng), 1.5)
    rms = lambda e: np.sqrt(np.mean(e**2, axis=0)).round(2).tolist()  # noqa: E731
    return {"seed": seed, "observer_rms_K": rms(estimate - true), "observer_max_K": np.abs(estimate - true).max(0)
            .round(2).tolist(), "thermistor_rms_K": rms(measured - true),
            "thermistor_max_K": np.abs(measured - true).max(0).round(2).tolist()}


def soak(seed: int, estimator: str) -> dict:
    rng = np.random.default_rng(seed)
    profile = PROFILES["random"](36000.0, 1.0, 3, rng)
    plant = ThermalPlant(["a", "b", "c"], SPECS, PlantEffects.from_names(",".join(PLANT_EFFECTS)), rng=rng,
                         protection=ThermalProtection(estimator=estimator))
    start = time.perf_counter()
    true = drive(plant, profile, 3.0)[0]
    return {"seed": seed, "estimator": estimator, "max_true_winding_C": true.max(0).round(1).tolist(),
            "limit_C": [s.winding_limit_C for s in SPECS], "wall_s": round(time.perf_counter() - start, 1)}


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, nargs="+", default=[0, 1])
    parser.add_argument("--json", action="store_true", help="print the record last, on one line")
    args = parser.parse_args(argv)
    record = {"tracking": [tracking(s) for s in args.seeds],
              "soak": [soak(s, e) for s in args.seeds for e in ("measured", "observer")]}
    for row in record["tracking"]:
        print(f"seed {row['seed']}: winding estimate error rms {row['observer_rms_K']} K, worst "
              f"{row['observer_max_K']} K; thermistor rms {row['thermistor_rms_K']} K, worst {row['thermistor_max_K']} K")
    for row in record["soak"]:
        print(f"10 h soak, seed {row['seed']}, protection on the {row['estimator']:8s}: hottest true winding "
              f"{row['max_true_winding_C']} degC (limits {row['limit_C']}), {row['wall_s']} s")
    if args.json:
        print(json.dumps(record))
    return record


if __name__ == "__main__":
    main()
