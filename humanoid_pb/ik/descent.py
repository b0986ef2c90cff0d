"""Finding a thermally minimising configuration for a contact mode: Jorgensen et al.'s descent, kept to
compare.

Jorgensen et al.'s naive method (Eqs. 29-32): on a basis ``V`` of the directions
that keep the contacts still (the null space of ``J_c``), a finite-difference
directional gradient of the potential ``f(q)`` (Eq. 30); a step
``dq = -k_p grad f`` with the gain chosen so that no coordinate moves more
than ``delta_max`` (Eq. 31); ``q <- q + N_c dq`` (Eq. 32); stop at the
iteration limit or when the next iterate would raise the cost.  Each
evaluation of ``f`` runs the whole-body statics (Eq. 23) and Eqs. 24-26.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
import pinocchio as pin

from ..constants import FOOT_SIDE, mode_feet
from ..model.statics import WholeBody


@dataclass(frozen=True)
class DescentResult:
    """Where Jorgensen et al.'s descent stopped: the configuration and its potential under Eq. 23's
    torques."""

    mode: str
    q: np.ndarray
    potential: float
    iterations: int
    wall_s: float
    history: list[float] = field(default_factory=list)
    contact_drift_m: float = 0.0  # largest sole displacement from the start (m)


def potential_of(body: WholeBody, q: np.ndarray, mode: str, potential) -> float:
    """The objective (a :class:`ThermalPotential` or :class:`MinimumEffort`) at ``q`` in ``mode``."""
    return potential.value(body.statics(q, mode).efforts)


def contact_drift(body: WholeBody, q0: np.ndarray, q: np.ndarray, mode: str) -> float:
    start, end = body.sole_poses(q0), body.sole_poses(q)
    sides = [FOOT_SIDE[f] for f in mode_feet(mode)]
    return float(max(np.linalg.norm(end[s].translation - start[s].translation) for s in sides))


def descent_step(body: WholeBody, q: np.ndarray, mode: str, potential, f: float | None = None,
                 delta_max: float = 0.01, h: float = 1e-4) -> tuple[np.ndarray, float, bool]:
    """One iteration of Jorgensen et al.'s descent (Eqs. 30-32): ``(q_next, f_next, moved)``.

    The step is bounded by ``delta_max`` in its largest coordinate (Eq. 31's
    gain: a trust region) and projected into the contacts' dynamically
    consistent null space (Eq. 32).  ``moved`` is false when the step would
    not lower the potential (the descent's stopping rule); then ``q`` is
    returned unchanged.  This is the unit Jorgensen et al. propose to run inside a
    whole-body controller, one per control step.
    """
    f = potential_of(body, q, mode, potential) if f is None else f
    Jc = body.contact_jacobian(q, mode)
    _, s, Vt = np.linalg.svd(Jc)
    V = Vt[np.sum(s > 1e-9):].T  # directions that keep every contact still (nv x |V|)
    grad = np.zeros(body.nv)
    for v in V.T:  # Eq. 30
        grad += v * (potential_of(body, pin.integrate(body.model, q, h * v), mode, potential) - f) / h
    dq = -grad
    scale = np.max(np.abs(dq))
    if scale == 0:
        return q, f, False
    dq *= delta_max / scale  # Eq. 31: the gain bounds the largest coordinate change by delta_max
    _, _, Nc = body.contact_null_space(q, Jc)
    q_next = pin.integrate(body.model, q, Nc @ dq)  # Eq. 32
    f_next = potential_of(body, q_next, mode, potential)
    if f_next >= f:
        return q, f, False
    return q_next, f_next, True


def naive_descent(body: WholeBody, q0: np.ndarray, mode: str, potential,
                  delta_max: float = 0.01, h: float = 1e-4, max_iter: int = 300) -> DescentResult:
    """Jorgensen et al.'s contact-consistent finite-difference descent (Eqs. 29-32), iterated to its stopping
    rule."""
    start = time.perf_counter()
    q = q0.copy()
    f = potential_of(body, q, mode, potential)
    history = [f]
    iterations = 0
    for iterations in range(1, max_iter + 1):
        q, f, moved = descent_step(body, q, mode, potential, f, delta_max, h)
        if not moved:
            break
        history.append(f)
    return DescentResult(mode, q, f, iterations, time.perf_counter() - start, history,
                         contact_drift(body, q0, q, mode))
