"""Thermal protection: how much of the commanded effort an actuator may have near its winding limit.

:class:`ThermalProtection` says how the plant derates (the margin, what temperature it acts on, the observer's
guard); :meth:`ThermalProtection.share` turns the temperature it acts on -- and, with the winding observer,
its cap on the current -- into each actuator's allowed fraction, for one control interval or every interval
of a block.  The plant (:mod:`.plant`) calls it every control period through
:meth:`~thermolimb.plant.ThermalPlant.protection_fraction`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class ThermalProtection:
    """Derating near the winding limit, as HEBI firmware caps output power.

    The allowed effort fraction falls linearly from 1 at ``margin_K`` below an
    actuator's winding limit (``ActuatorSpec.winding_limit_C``) to
    ``min_fraction`` at the limit.  ``estimator`` says which temperature it
    acts on: ``"observer"`` (default) the winding estimated by a
    :class:`~thermolimb.plant.observer.WindingObserver` from the measured current and
    thermistor, plus ``sigmas`` of its uncertainty; ``"measured"`` the lagged
    thermistor reading itself, which lets the true winding overshoot.  With
    the observer the current is also capped so that the winding predicted at
    the end of the next interval stays ``guard_K`` plus ``sigmas`` below
    the limit (see :meth:`ThermalPlant.derate`).
    """

    margin_K: float = 15.0
    min_fraction: float = 0.0
    estimator: str = "observer"
    sigmas: float = 2.0
    guard_K: float = 4.0  # what the observer's model may miss over one control period (measured: a few K)

    def __post_init__(self):
        if self.estimator not in ("observer", "measured"):
            raise ValueError("ThermalProtection estimator must be 'observer' "
                             f"or 'measured', got {self.estimator!r}")
        if not self.margin_K > 0:
            raise ValueError(f"ThermalProtection needs margin_K > 0, got {self.margin_K}")
        if not 0.0 <= self.min_fraction <= 1.0:
            raise ValueError(f"ThermalProtection needs 0 <= min_fraction <= 1, got {self.min_fraction}")

    def fraction(self, temperature_C: np.ndarray, limit_C: np.ndarray) -> np.ndarray:
        """Allowed fraction of the commanded effort, per actuator; a temperature that is not a number (a
        sensor that failed) is taken as at the limit: the protection fails safe."""
        frac = (np.asarray(limit_C) - np.asarray(temperature_C)) / self.margin_K
        return np.clip(np.where(np.isnan(frac), self.min_fraction, frac), self.min_fraction, 1.0)

    def acted_on_C(self, measured_C: np.ndarray, observer) -> np.ndarray:
        """The winding temperature protection acts on (degC): the observer's estimate plus ``sigmas`` of its
        uncertainty, or without an observer the measured temperature."""
        if observer is None:
            return np.array(measured_C, float)
        return observer.winding_C + self.sigmas * observer.winding_std_K

    def share(self, protected_C: np.ndarray, limit_C: np.ndarray, std_K: np.ndarray | None = None,
              cap=None) -> np.ndarray:
        """Protection's share from the temperature it acts on and, given ``cap`` (the observer's current cap
        as a function of the temperature the winding must stay below), the limit less ``guard_K`` and
        ``sigmas`` standard deviations: for one interval, or every interval of a block."""
        fraction = self.fraction(protected_C, limit_C)
        if cap is None:
            return fraction
        return np.minimum(fraction, cap(np.asarray(limit_C) - (self.guard_K + self.sigmas * std_K)))


@dataclass(frozen=True)
class ThermalLimits:
    """A robot's temperatures (degC), one shape for every robot: each actuator's winding limit (its actuator
    order), where the robot is called hot (an environment's penalty, a recovery's start) and, when it has a
    recovery to make, where it counts as cool again."""

    winding_C: tuple[float, ...]  # per actuator: the plant's protection derates its margin below this
    warning_C: float
    recovered_C: float | None = None  # every actuator below this: recovered (None: no recovery is studied)

    @property
    def winding_limits_C(self) -> np.ndarray:
        return np.asarray(self.winding_C, float)


def scale_efforts(effort: np.ndarray, fraction: np.ndarray, bias: float = 0.0) -> np.ndarray:
    """Efforts whose motor share (all of it, less a series-elastic ``bias``) is scaled by ``fraction``."""
    return bias + (np.asarray(effort, dtype=float) - bias) * fraction
