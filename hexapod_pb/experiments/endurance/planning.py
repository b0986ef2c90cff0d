"""The gait whose measured torques the identified models say run coolest, at a kept share of the stock
speed."""

from __future__ import annotations

from dataclasses import dataclass, replace
from itertools import product

import numpy as np

from thermolimb.model import ModelArrays

from ...control.controller import ThermalContext
from .cycle import Cycle, _with_pause, measure_cycle
from .gait import GAIT_CHOICES, NOMINAL_GAIT, Gait

MIN_SPEED_SHARE = 0.8  # a planned gait keeps at least this share of the nominal gait's measured speed


def predicted_peak_C(bank: ModelArrays, cycle: Cycle, pause: Cycle | None = None,
                     pause_share: float = 0.0) -> float:
    """The hottest equilibrium the identified models predict for a cycle's mean heating (degC), with
    ``pause_share`` of the time spent in the ``pause`` cycle."""
    mean_sq, mean = _with_pause(cycle, pause, pause_share)
    return float(
        np.max(bank.betaR_K_per_effort2 * mean_sq - bank.beta_biasR_K_per_effort * mean + bank.T_offset_C)
    )


@dataclass(frozen=True)
class GaitPlan:
    gait: Gait
    predicted_peak_C: float
    nominal_predicted_peak_C: float
    distance_per_s_m: float
    nominal_distance_per_s_m: float
    candidates: int


def plan_gait(payload_kg: float, mode: str, ambient_C: float, bank: ModelArrays, seed: int = 0,
              choices: dict[str, tuple[float, ...]] = GAIT_CHOICES) -> GaitPlan:
    """The gait whose measured torques the identified models say run coolest, at >= 80 % of the stock speed.

    Standing, only the reach and height change (the duty factor and pauses
    do not exist).  A pause's standing duty is measured once per reach and
    height and weighed in by its share of the time.
    """
    thermal = ThermalContext(bank)
    nominal = measure_cycle(payload_kg, mode, "thermal_aware", ambient_C, NOMINAL_GAIT, thermal=thermal,
                            seed=seed)
    stock = measure_cycle(payload_kg, mode, "vertical_only", ambient_C, NOMINAL_GAIT, seed=seed)
    # the speed to keep is the stock controller's (vertical forces on the nominal gait), or this one's if
    # faster
    reference = max(nominal.distance_per_s_m, stock.distance_per_s_m)
    walking = mode == "walk"
    duties = choices["duty_factor"] if walking else (NOMINAL_GAIT.duty_factor,)
    pauses = choices.get("pause_share", (0.0,)) if walking else (0.0,)
    best = (
        predicted_peak_C(bank, nominal) if not nominal.fell else np.inf,
        NOMINAL_GAIT,
        nominal.distance_per_s_m,
    )
    count, standing = 1, {}
    for duty, reach, height in product(duties, choices["foot_reach_m"], choices["body_height_m"]):
        gait = Gait(duty, reach, height)
        if gait == NOMINAL_GAIT:
            cycle = nominal
        else:
            cycle = measure_cycle(payload_kg, mode, "thermal_aware", ambient_C, gait, thermal=thermal,
                                  seed=seed)
            count += 1
        if cycle.fell:
            continue
        for share in pauses:
            distance = (1 - share) * cycle.distance_per_s_m
            if (share == 0.0 and gait == NOMINAL_GAIT) or distance < MIN_SPEED_SHARE * reference:
                continue
            pause = None
            if share > 0.0:
                if (reach, height) not in standing:
                    standing[reach, height] = measure_cycle(payload_kg, "stand", "thermal_aware", ambient_C,
                                                            gait, thermal=thermal, seed=seed)
                pause = standing[reach, height]
                count += 1
                if pause.fell:
                    continue
            peak = predicted_peak_C(bank, cycle, pause, share)
            if peak < best[0]:
                best = (peak, replace(gait, pause_share=share), distance)
    return GaitPlan(best[1], float(best[0]), predicted_peak_C(bank, nominal), best[2], reference, count)
