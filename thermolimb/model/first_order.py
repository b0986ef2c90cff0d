"""Many first-order models at once: Jorgensen et al.'s Joule heating, an effort bias and copper's coefficient on one
node, whose forcing is a polynomial in the effort, held as arrays so that a whole robot's (or a fleet's) actuators
step together (the Gymnasium wrapper, the monitor) exactly as :meth:`ThermalModel.simulate` steps each."""

from __future__ import annotations

from typing import Sequence

import numpy as np

from ..constants import COPPER_REFERENCE_C

FAMILY = frozenset({"joule", "effort_bias", "winding_tempco"})  # one node, forcing polynomial in the effort


def in_family(model) -> bool:
    return set(model.terms) <= FAMILY


class FirstOrderArrays:
    """The parameters of first-order models (each :func:`in_family`), one entry per model."""

    def __init__(self, models: Sequence):
        p = [m.params for m in models]
        self.rc = np.array([q["RC_s"] for q in p])
        self.offset = np.array([q["T_offset_C"] for q in p])
        self.b = np.array([q.get("betaR_K_per_effort2", 0.0) for q in p])
        self.c = np.array([q.get("beta_biasR_K_per_effort", 0.0) for q in p])
        self.alpha = np.array([q.get("alpha_per_K", 0.0) for q in p])
        self.copper = bool(self.alpha.any())

    def forcing(self, effort: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(steady_C, rate_per_s)`` each model heads for under ``effort`` held (its ``dT/dt = rate (steady - T)``);
        the rate is the winding's own unless copper's coefficient makes it depend on the heat."""
        heat = self.b * effort**2
        if not self.copper:
            return self.offset + heat - self.c * effort, 1.0 / self.rc
        restoring = np.maximum(1.0 - self.alpha * heat, 1e-6)
        steady = (self.offset + heat - self.c * effort - self.alpha * COPPER_REFERENCE_C * heat) / restoring
        return steady, restoring / self.rc
