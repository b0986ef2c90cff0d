"""Whether a model fitted on some runs carries to a run it was not fitted on, and where it does not, what
differs between the runs.

A model validated on another run of the same joint may stay many times the sensor's floor there: the other
run was driven harder, ran in other air, only heated, or started elsewhere, and the model never saw that.  The
workbench says so beside the held-out error, naming the run and the differences the two logs show, so that a
user reads "does not carry" as a property of the runs, not a failed fit.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from ..logs import ActuatorSeries
from .floor import sensor_floor

CARRY_FLOOR_FACTOR = 5.0  # a held-out run's error over this many times the sensor's floor ...
CARRY_TRAIN_FACTOR = 2.0  # ... and this many times the training error: the model does not carry to it
WIDER = 1.25  # a held-out run's effort beyond the fitted runs' largest by this factor is said
AIR_K = 5.0  # ambients (or starts) this far apart are said
FINEST_K = 1e-3  # a floor under this (readings averaged or written at full precision) is said as under it
COOLS = 0.05  # a run whose readings never fall below their highest by this share of its rise only heats


def carry_flags(segments, fitted: Sequence[ActuatorSeries], held: Sequence[ActuatorSeries],
                train_rmse_K: float) -> list[str]:
    """A sentence for each held-out run the model does not carry to (its error over
    :data:`CARRY_FLOOR_FACTOR` times the sensor's floor and :data:`CARRY_TRAIN_FACTOR` times
    ``train_rmse_K``), naming what differs between it and the ``fitted`` runs.

    Parameters
    ----------
    segments
        The held-out validation segments (each with its ``unit``: the run's label).
    fitted, held
        The runs the model was fitted on, and the held-out runs, in the order their labels number them.
    train_rmse_K
        The model's error on the data it was fitted on (K).
    """
    out = []
    for k, run in enumerate(held):
        label = run.run or f"run {k + 1}"
        mine = [s for s in segments if s.unit == label]
        if not mine:
            continue
        error = np.concatenate([s.measured_C - s.simulated_C for s in mine])
        rmse = float(np.sqrt(np.mean(error ** 2)))
        floor = sensor_floor([run]).floor_K
        if not (rmse > CARRY_FLOOR_FACTOR * floor and rmse > CARRY_TRAIN_FACTOR * train_rmse_K):
            continue
        differs = differences(fitted, run)
        why = "; ".join(differs) if differs else ("the runs differ in nothing this check reads (effort, "
                                                  "ambient, heating and cooling, start)")
        against = (f"{rmse / floor:.0f} times the sensor's floor ({floor:.3g} K)" if floor >= FINEST_K
                   else f"the sensor's floor under {FINEST_K:g} K")
        out.append(f"the model does not carry to {label}: held-out RMSE {rmse:.3g} K, {against} and "
                   f"{rmse / max(train_rmse_K, 1e-12):.0f} times its training error; {why}")
    return out


def differences(fitted: Sequence[ActuatorSeries], run: ActuatorSeries) -> list[str]:
    """What differs between the ``fitted`` runs and ``run``, in words: the effort's range, the air, whether
    each cools, where each starts."""
    out = []
    unit = run.units.get("effort") or ""
    unit = f" {unit}" if unit else ""
    peak = max(float(np.max(np.abs(s.signals.effort))) for s in fitted)
    own = float(np.max(np.abs(run.signals.effort)))
    if own > WIDER * peak or own < peak / WIDER:
        out.append(f"its effort reaches {own:.3g}{unit}, the fitted runs' {peak:.3g}{unit}")
    air = [float(np.mean(s.signals.ambient_C)) for s in fitted if s.signals.ambient_C is not None]
    if air and run.signals.ambient_C is not None:
        own_air = float(np.mean(run.signals.ambient_C))
        if min(abs(own_air - a) for a in air) > AIR_K:
            out.append(f"it ran in {own_air:.1f} degC air, the fitted runs in "
                       f"{', '.join(f'{a:.1f}' for a in air)} degC")
    heats = [only_heats(s) for s in fitted]
    if only_heats(run) and not any(heats):
        out.append("it only heats, where the fitted runs cool too")
    elif all(heats) and not only_heats(run):
        out.append("it cools, where the fitted runs only heat")
    starts = [float(s.temperature_C[0]) for s in fitted]
    if min(abs(run.temperature_C[0] - t) for t in starts) > AIR_K:
        out.append(f"it starts at {run.temperature_C[0]:.1f} degC, the fitted runs at "
                   f"{', '.join(f'{t:.1f}' for t in starts)} degC")
    return out


def only_heats(run: ActuatorSeries) -> bool:
    """Whether the run's readings never fall below their highest so far by more than :data:`COOLS` of its
    rise."""
    t = run.temperature_C
    rise = float(np.max(t) - t[0])
    return rise > 0.0 and float(np.max(np.maximum.accumulate(t) - t)) <= COOLS * rise
