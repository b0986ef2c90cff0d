"""The thermal potential of a configuration: Jorgensen et al.'s Eqs. 25-26.

For actuator efforts ``F(q)`` (Eq. 24 of the statics) and measured
temperatures ``T0``, each actuator's temperature a horizon ``dt`` ahead is

    T_i = T0_i e^(-dt/RC_i) + (F_i^2 betaR_i - F_i beta_biasR_i + T_offset_i)(1 - e^(-dt/RC_i))   (Eq. 25)

and the potential is ``f = T' Q T`` (Eq. 26) with ``Q`` diagonal: 1 by
default, raised for actuators measured above 70 degC so that the hot ones
dominate, as in Jorgensen et al..  The horizon is half the learned time constant
(Jorgensen et al.: ``dt = RC/2``, 20 s on Valkyrie).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from thermolimb.model import ModelArrays

from ..limits import LIMITS

HOT_WEIGHT = 100.0  # an actuator still to recover (above LIMITS.recovered_C) weighs this much more


@dataclass(frozen=True)
class ThermalPotential:
    bank: ModelArrays  # identified models, ACTUATORS order
    temperature_C: np.ndarray  # measured now
    horizon_s: float
    weights: np.ndarray  # the diagonal of Q

    @classmethod
    def from_measurement(
        cls,
        bank: ModelArrays,
        temperature_C: np.ndarray,
        horizon_s: float | None = None,
        hot_C: float = LIMITS.recovered_C,
        hot_weight: float = HOT_WEIGHT,
    ) -> "ThermalPotential":
        """Q = I, raised to ``hot_weight`` for actuators above ``hot_C``; horizon RC/2 (median over
        actuators)."""
        temperature_C = np.asarray(temperature_C, float)
        horizon = float(np.median(bank.RC_s)) / 2.0 if horizon_s is None else float(horizon_s)
        weights = np.where(temperature_C > hot_C, hot_weight, 1.0)
        return cls(bank, temperature_C, horizon, weights)

    @cached_property
    def _quadratic(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Eq. 25 as ``T = a + b F + c F^2`` per actuator (the horizon's decay computed once)."""
        return self.bank.ahead_coefficients(self.temperature_C, self.horizon_s)

    def predicted_C(self, efforts: np.ndarray) -> np.ndarray:
        """Eq. 25 for efforts held over the horizon."""
        a, b, c = self._quadratic
        return a + efforts * (b + c * efforts)

    def value(self, efforts: np.ndarray) -> float:
        """Eq. 26."""
        T = self.predicted_C(efforts)
        return float(T @ (self.weights * T))

    def gradient(self, efforts: np.ndarray) -> np.ndarray:
        """d f / d efforts (the Jacobian of Eq. 25 is diagonal)."""
        return self.newton(efforts)[1]

    def hessian_diag(self, efforts: np.ndarray) -> np.ndarray:
        """d2 f / d efforts2 (diagonal, >= 0: T >= 0 and convex in the effort): 2 w (T'^2 + T T'')."""
        return self.newton(efforts)[2]

    def newton(self, efforts: np.ndarray) -> tuple[float, np.ndarray, np.ndarray]:
        """Value, gradient and Hessian diagonal at once (one evaluation of Eq. 25)."""
        _, b, c = self._quadratic
        T = self.predicted_C(efforts)
        slope = b + 2.0 * c * efforts
        wT = self.weights * T
        return float(T @ wT), 2.0 * wT * slope, 2.0 * self.weights * (slope**2 + 2.0 * c * T)


@dataclass(frozen=True)
class MinimumEffort:
    """The baseline without thermal information: ``f = sum (F_i / F_max_i)^2`` (Eq. 23's efforts in Eq. 26).

    Efforts are normalised by their limits so that rod forces (N) and motor
    torques (N m) can be summed.
    """

    limits: np.ndarray  # ACTUATORS order

    def value(self, efforts: np.ndarray) -> float:
        e = efforts / self.limits
        return float(e @ e)

    def gradient(self, efforts: np.ndarray) -> np.ndarray:
        return 2.0 * efforts / self.limits**2

    def hessian_diag(self, efforts: np.ndarray) -> np.ndarray:
        return np.broadcast_to(2.0 / self.limits**2, np.shape(efforts))

    def newton(self, efforts: np.ndarray) -> tuple[float, np.ndarray, np.ndarray]:
        """Value, gradient and Hessian diagonal at once."""
        return self.value(efforts), self.gradient(efforts), self.hessian_diag(efforts)
