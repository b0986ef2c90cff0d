"""The thermal minimax: stance forces that minimise the hottest *predicted* temperature of the stance legs'
actuators (Jorgensen et al.'s Eq. 25 on identified models), by Kelley's cutting planes on the stance LP."""

from __future__ import annotations

import time
from dataclasses import replace

import numpy as np

from thermolimb.model import ModelArrays
from thermolimb.optimization.programs import INFINITE, Program, solve

from .minimax import lp_options, minimax
from .stance import StanceProblem, StanceSolution


def thermal_minimax(problem: StanceProblem, bank: ModelArrays, temperature_C: np.ndarray, horizon_s: float,
                    tol_K: float = 1e-3, max_cuts: int = 30, first: StanceSolution | None = None,
                    solver: str = "daqp", fallback: str | None = None) -> StanceSolution:
    """Minimise the peak *predicted* temperature of the stance legs' actuators ``horizon_s`` ahead.

    With Eq. 25 each predicted temperature is a convex quadratic of its
    joint's torque, ``T_j = a_j + b_j tau_j + c_j tau_j^2``; the minimax of
    these is solved by Kelley's cutting planes on the LP: each round adds the
    tangent of every ``T_j`` at the current torques, until the model's peak is
    within ``tol_K`` of the true one.  ``bank`` and ``temperature_C`` are the
    stance joints' (3n) identified models and measured temperatures;
    ``first``: the torque minimax already solved for this problem (the
    first point), else solved here.  Every LP by ``solver`` (``fallback``
    only if named).
    """
    p = problem
    nf = 3 * p.n
    a, b, cq = bank.ahead_coefficients(temperature_C, horizon_s)
    E = p.equilibrium
    start = time.perf_counter()
    sol = first or minimax(p, solver, fallback=fallback)  # a good first point: the torque minimax
    fell_back = {sol.fallback_from} - {None}
    cuts_A, cuts_b = [], []
    # what every round shares: the wrench balance, the contact rows and the torques within 3x their scale (a
    # trust region for the cuts)
    extra_A, extra_bu, extra_bl = p.contact_rows
    fixed_A = np.vstack([extra_A, np.hstack([p.torque_map, np.zeros((nf, 1))])])
    fixed_bu = np.concatenate([extra_bu, 3 * p.torque_scale_Nm - p.gravity_Nm])
    fixed_bl = np.concatenate([extra_bl, -3 * p.torque_scale_Nm - p.gravity_Nm])
    balance = np.hstack([E, np.zeros((6, 1))])
    c = np.zeros(nf + 1)
    c[-1] = 1.0
    rounds = 0
    for rounds in range(1, max_cuts + 1):
        tau = p.torques(sol.forces_N)
        predicted = a + b * tau + cq * tau**2
        slope = b + 2 * cq * tau  # dT/dtau at tau
        # T_j(tau') >= T_j(tau) + slope (tau' - tau), and tau' = T f' + g:  slope T f' - t <= ...
        rows = np.hstack([slope[:, None] * p.torque_map, -np.ones((nf, 1))])
        rhs = -(predicted - slope * tau) - slope * p.gravity_Nm
        cuts_A.append(rows)
        cuts_b.append(rhs)
        A = np.vstack([balance, *cuts_A, fixed_A])
        bu = np.concatenate([p.wrench, *cuts_b, fixed_bu])
        bl = np.concatenate([p.wrench, np.full(sum(len(r) for r in cuts_b), -INFINITE), fixed_bl])
        found = solve(Program(c, A, bu, bl, n_eq=6, name="the thermal minimax's cutting-plane LP"), solver,
                      fallback, **lp_options(solver))
        fell_back |= {found.fallback_from} - {None}
        x = found.x
        sol = StanceSolution(p, x[:nf].reshape(-1, 3), "thermal_aware", found.solver, 0.0, rounds, found)
        tau = p.torques(sol.forces_N)
        true_peak = float(np.max(a + b * tau + cq * tau**2))
        if true_peak - x[-1] <= tol_K:
            break
    return replace(sol, solve_time_s=time.perf_counter() - start, iterations=rounds,
                   fallback_from="; ".join(sorted(fell_back)) or None)
