"""The contact-mode planner of Jorgensen et al.'s Eq. 33, shared by the recovery experiment and the
environment's policies.

For each contact mode (double support, left, right) the fast thermal IK
finds the configuration that minimises the objective from that mode's
start; the mode whose best configuration scores lowest is chosen.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from thermolimb.model import ModelArrays

from ..constants import CONTACT_MODES, SIDES
from ..ik.fast_ik import FastThermalIK
from ..ik.poses import support_pose
from ..ik.potential import MinimumEffort, ThermalPotential
from ..model.actuation import effort_limits

OBJECTIVES = ("thermal", "effort")


@dataclass(frozen=True)
class Plan:
    mode: str
    results: dict  # mode -> the IK's result from that mode's start


def best_mode(results: dict) -> str:
    """Jorgensen et al.'s Eq. 33: of each contact mode's best configuration (``{mode: result with
    .potential}``), the mode whose result scores lowest.  The one place the choice is made, whatever found
    each mode's configuration."""
    return min(results, key=lambda m: results[m].potential)


class ContactModePlanner:
    """Eq. 33 over the contact modes with an objective: ``"thermal"`` (Eq. 25's potential) or ``"effort"``."""

    def __init__(self, body, objective: str, max_iter: int = 15):
        if objective not in OBJECTIVES:
            raise ValueError(f"objective must be 'thermal' or 'effort', got {objective!r}")
        self.body = body
        self.objective = objective
        self.max_iter = max_iter
        self.ik = FastThermalIK(body, solver="daqp")
        self.limits = effort_limits(body.params)

    def cost(self, bank: ModelArrays | None, temperature_C: np.ndarray):
        if self.objective == "thermal":
            return ThermalPotential.from_measurement(bank, temperature_C)
        return MinimumEffort(self.limits)

    def starts(self, q_nominal: np.ndarray) -> dict:
        """Each mode's nominal configuration: the crouch, and the weight over either foot with the other
        lifted."""
        return {"double": q_nominal, **{s: support_pose(self.body, q_nominal, s) for s in SIDES}}

    def plan(self, q_nominal: np.ndarray, bank: ModelArrays | None, temperature_C: np.ndarray) -> Plan:
        """The mode whose optimised configuration scores lowest (for a robot that then holds that
        configuration)."""
        cost = self.cost(bank, temperature_C)
        starts = self.starts(q_nominal)
        results = {m: self.ik.solve(starts[m], m, cost, max_iter=self.max_iter) for m in CONTACT_MODES}
        return Plan(best_mode(results), results)

    def plan_nominal(self, q_nominal: np.ndarray, bank: ModelArrays | None,
                     temperature_C: np.ndarray) -> str:
        """The mode whose nominal configuration, held with Eq. 23's torques, scores lowest: for a robot that
        switches modes but keeps their nominal postures (the environment's mode actions)."""
        cost = self.cost(bank, temperature_C)
        scores = {m: cost.value(self.body.statics(q, m).efforts) for m, q in self.starts(q_nominal).items()}
        return min(scores, key=scores.get)
