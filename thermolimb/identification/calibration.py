"""Eq. 5 for every actuator of a robot, identified from the robot's own log (what its controllers plan
with)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np

from ..logs import ThermalLog
from ..model import ModelArrays, ThermalModel
from ..model.terms import DEFAULT_MODEL
from ..util.errors import IdentifiabilityError
from .output_error import FreeRunLeastSquares


@dataclass(frozen=True)
class Calibration:
    """What a robot's calibration run gives its planners: the models identified from its log, the log, and the
    ambient it measured cold (degC; its thermistors' mean first reading).  Every robot's ``calibrate`` returns
    one."""

    bank: ModelArrays
    log: ThermalLog
    ambient_C: float


def measured_ambient_C(log: ThermalLog) -> float:
    """The ambient a robot measures cold: the mean of its actuators' first temperature readings (degC)."""
    return float(np.mean([log.series(name).temperature_C[0] for name in log.actuators]))


# default: a time constant below this is not physical for a humanoid's windings: not identified
MIN_RC_S = 5.0


def identify_bank(log: ThermalLog, actuators: Sequence[str], limits: np.ndarray, min_rc_s: float = MIN_RC_S,
                  model: str | tuple[str, ...] = DEFAULT_MODEL, min_rise_K: float = 0.0) -> ModelArrays:
    """Fit Eq. 5 (output error, ``model``: ``joule`` with or without ``effort_bias``) to every named actuator
    of ``log``, in that order.

    Actuators the log cannot identify (efforts that barely change, a fit
    with a time constant below ``min_rc_s``, implausible for the winding, or
    efforts whose Joule heating the fit puts below ``min_rise_K`` on average,
    i.e. within the sensor's resolution) get a prior rather than "no heating",
    which an optimiser would exploit: the identified actuators' median
    ``betaR * limit^2`` over their own ``limit^2`` (``limits``, the effort
    limits: current scales with them for actuators of one family), the median
    time constant, and the mean measured temperature as offset.
    """
    models: dict[str, ThermalModel | None] = {}
    for name in actuators:
        try:
            series = log.series(name)
            m = FreeRunLeastSquares(model=model).fit(series).model_
            rise = m.params["betaR_K_per_effort2"] * float(np.mean(np.asarray(series.signals.effort) ** 2))
            models[name] = m if m.params["RC_s"] >= min_rc_s and rise >= min_rise_K else None
        except (IdentifiabilityError, ValueError):
            models[name] = None
    known = [(m, limits[i]) for i, m in enumerate(models.values()) if m is not None]
    if not known:
        raise IdentifiabilityError("the calibration log identifies no actuator: it needs efforts that vary")
    rc = float(np.median([m.params["RC_s"] for m, _ in known]))
    heat = float(np.median([m.params["betaR_K_per_effort2"] * lim**2 for m, lim in known]))
    filled = []
    for i, name in enumerate(actuators):
        m = models[name]
        if m is None:
            T = float(np.mean(log.series(name).temperature_C))
            m = ThermalModel(DEFAULT_MODEL, {"RC_s": rc, "betaR_K_per_effort2": heat / limits[i] ** 2,
                             "beta_biasR_K_per_effort": 0.0, "T_offset_C": T})
        filled.append(m)
    return ModelArrays.from_models(filled)
