"""Jorgensen et al.'s model for many actuators at once: Eq. 6 / Eq. 25 vectorised.

A controller (the humanoid's thermal IK, the hexapod's thermal-aware wrench
distribution) needs, for every actuator ``i`` and a candidate effort vector
``F``, the temperature a horizon ``dt`` ahead:

    T_i(dt) = T0_i exp(-dt/RC_i) + (F_i^2 betaR_i - F_i beta_biasR_i + T_offset_i)(1 - exp(-dt/RC_i))

and its derivative with respect to ``F``.  All arrays have one entry per actuator.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np

from .model import ThermalModel
from .terms import DEFAULT_MODEL

_BANK_TERMS = set(DEFAULT_MODEL)  # Eq. 5: the default model's terms


@dataclass(frozen=True)
class FirstOrderBank:
    """Parameters of Eq. 5 for ``n`` actuators (arrays of shape ``(n,)``)."""

    RC_s: np.ndarray
    betaR_K_per_effort2: np.ndarray
    beta_biasR_K_per_effort: np.ndarray
    T_offset_C: np.ndarray

    def __post_init__(self):
        arrays = [np.atleast_1d(np.asarray(getattr(self, f), dtype=float)) for f in self.__dataclass_fields__]
        n = arrays[0].shape[0]
        for name, arr in zip(self.__dataclass_fields__, arrays):
            if arr.shape != (n,):
                raise ValueError(f"FirstOrderBank.{name} has shape {arr.shape}, expected ({n},)")
            object.__setattr__(self, name, arr)
        if np.any(self.RC_s <= 0):
            raise ValueError(f"RC_s must be positive, got {self.RC_s}")

    @property
    def n(self) -> int:
        return int(self.RC_s.shape[0])

    @classmethod
    def from_specs(cls, specs: Sequence, ambient_C: float = 25.0, lumped_nodes: int = 1) -> "FirstOrderBank":
        """Eq. 5 from actuator datasheets (:meth:`thermolimb.plant.ActuatorSpec.first_order`, no effort bias):
        what a controller can plan with before any log is identified."""
        rc, beta = zip(*(spec.first_order(lumped_nodes) for spec in specs))
        n = len(rc)
        return cls(np.array(rc), np.array(beta), np.zeros(n), np.full(n, float(ambient_C)))

    @classmethod
    def from_models(cls, models: Sequence[ThermalModel]) -> "FirstOrderBank":
        """Stack fitted single-actuator models whose terms are within joule and effort_bias."""
        for m in models:
            extra = set(m.terms) - _BANK_TERMS
            if extra:
                raise ValueError(f"FirstOrderBank holds Eq. 5 only; model has extra terms {sorted(extra)}")
        return cls(
            RC_s=np.array([m.params["RC_s"] for m in models]),
            betaR_K_per_effort2=np.array([m.params.get("betaR_K_per_effort2", 0.0) for m in models]),
            beta_biasR_K_per_effort=np.array([m.params.get("beta_biasR_K_per_effort", 0.0) for m in models]),
            T_offset_C=np.array([m.params["T_offset_C"] for m in models]),
        )

    def subset(self, indices) -> "FirstOrderBank":
        """The bank of the actuators at ``indices`` (an index array or boolean mask), in that order."""
        return FirstOrderBank(self.RC_s[indices], self.betaR_K_per_effort2[indices],
                              self.beta_biasR_K_per_effort[indices], self.T_offset_C[indices])

    def equilibrium_C(self, effort: np.ndarray) -> np.ndarray:
        """Steady-state temperatures for efforts held forever."""
        return effort**2 * self.betaR_K_per_effort2 - effort * self.beta_biasR_K_per_effort + self.T_offset_C

    def ahead(self, initial_C: np.ndarray, effort: np.ndarray, horizon_s: float | np.ndarray) -> np.ndarray:
        """Eq. 25: temperatures ``horizon_s`` ahead with efforts held constant.

        ``effort`` may carry leading batch dimensions, ``(..., n)``.
        """
        decay = np.exp(-np.asarray(horizon_s) / self.RC_s)
        return initial_C * decay + self.equilibrium_C(effort) * (1.0 - decay)

    def ahead_coefficients(self, initial_C: np.ndarray, horizon_s: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(a, b, c)`` with :meth:`ahead` ``= a + b F + c F^2`` per actuator: Eq. 25 as a quadratic in effort."""
        decay = np.exp(-np.asarray(horizon_s) / self.RC_s)
        return (initial_C * decay + self.T_offset_C * (1.0 - decay), -self.beta_biasR_K_per_effort * (1.0 - decay),
                self.betaR_K_per_effort2 * (1.0 - decay))

    def ahead_gradient(self, effort: np.ndarray, horizon_s: float | np.ndarray) -> np.ndarray:
        """d T_i(horizon) / d F_i (the Jacobian is diagonal), same shape as ``effort``."""
        decay = np.exp(-np.asarray(horizon_s) / self.RC_s)
        return (2.0 * effort * self.betaR_K_per_effort2 - self.beta_biasR_K_per_effort) * (1.0 - decay)

    def step(self, temperature_C: np.ndarray, effort: np.ndarray, dt_s: float, method: str = "exact") -> np.ndarray:
        """Advance all actuators by one interval with efforts held: exact (ZOH) or forward Euler."""
        if method == "exact":
            return self.ahead(temperature_C, effort, dt_s)
        if method == "euler":
            return temperature_C + dt_s / self.RC_s * (self.equilibrium_C(effort) - temperature_C)
        raise ValueError(f"method must be 'exact' or 'euler', got {method!r}")
