"""Nair et al.'s way of solving the stance minimax: normal forces from statics, then ``scipy``'s trust-constr
over the friction components of a tripod, on the non-smooth peak of normalised torque (the baseline the exact
LP of :mod:`.minimax` is measured against in ``benchmarks/wrench.py``)."""

from __future__ import annotations

import time
import warnings

import numpy as np
from scipy.optimize import LinearConstraint, minimize

from .stance import StanceProblem, StanceSolution, vertical_only


def nair_trust_constr(problem: StanceProblem, zero_hessian: bool = True, x0: np.ndarray | None = None,
                      maxiter: int = 500) -> StanceSolution:
    """Nair et al.'s method: normal forces from statics, trust-constr over the friction components of a
    tripod.

    The cost ``max_j |tau_j| / s_j`` is non-smooth, as in Nair et al.; with
    ``zero_hessian`` the Hessian is taken as zero (Nair et al.'s 45 ms variant).
    Constraints: Nair et al.'s three friction equalities (x, y force and yaw moment).
    """
    p = problem
    if p.n != 3:
        raise ValueError(f"Nair et al.'s formulation is for a tripod; got {p.n} stance legs")
    start = time.perf_counter()
    normal = vertical_only(p).forces_N[:, 2]  # Nair et al.'s Eq. 9 (exact for three feet)
    x, y = p.body_p_feet[:, 0], p.body_p_feet[:, 1]
    A = np.vstack([np.r_[np.ones(3), np.zeros(3)], np.r_[np.zeros(3), np.ones(3)], np.r_[-y, x]])
    b = np.array([p.wrench[0], p.wrench[1], p.wrench[5] - 0.0])

    def forces(v):
        f = np.zeros((3, 3))
        f[:, 0], f[:, 1], f[:, 2] = v[:3], v[3:], normal
        return f

    def cost(v):
        return float(np.max(p.normalised(forces(v))))

    hess = (lambda v: np.zeros((6, 6))) if zero_hessian else None
    kwargs = {"hess": hess} if hess else {}
    with warnings.catch_warnings():
        # the quasi-Newton update warns that the cost is piecewise linear: that is why Nair et al. zeroed the
        # Hessian
        warnings.simplefilter("ignore", UserWarning)
        result = minimize(cost, np.zeros(6) if x0 is None else x0, method="trust-constr",
                          constraints=[LinearConstraint(A, b, b)], options={"maxiter": maxiter, "verbose": 0},
                          **kwargs)
    return StanceSolution(p, forces(result.x), "nair_trust_constr", "trust-constr",
                          time.perf_counter() - start, int(result.nit))
