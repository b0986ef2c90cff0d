"""The exact minimax of the peak normalised torque (an LP, :func:`minimax`), its second stage among the
distributions sharing the optimal peak (a QP, :func:`minimax_lex`), and the nearest wrench the contacts can
supply (:func:`closest_achievable`), each solved by the solver its caller names (``daqp`` or HiGHS)."""

from __future__ import annotations

import time
from dataclasses import replace

import numpy as np

from thermolimb.optimization.programs import INFINITE, Program, SolverError, solve

from .stance import StanceProblem, StanceSolution

# daqp's proximal iterations for an LP (it has no Hessian to regularise)
DAQP_LP_OPTIONS = {"eps_prox": 1e-6}


def lp_options(solver: str) -> dict:
    """Options of ``solver`` for an LP (daqp: its proximal iterations, as an LP has no Hessian to
    regularise)."""
    return DAQP_LP_OPTIONS if solver == "daqp" else {}


MOMENT_ARM_M = 0.3  # weights moment errors against force errors in the closest achievable wrench


def closest_achievable(
    problem: StanceProblem, solver: str = "daqp", fallback: str | None = None
) -> StanceProblem:
    """The same problem with its wrench replaced by the nearest one the contacts can supply.

    Minimises ``|E f - w|_1`` (moments divided by a 0.3 m arm) subject to the
    friction pyramid and unilateral constraints, by ``solver`` (``fallback``
    only if named); returns ``problem`` itself when its wrench is already
    achievable.
    """
    p = problem
    nf = 3 * p.n
    weights = np.r_[np.ones(3), np.full(3, 1.0 / MOMENT_ARM_M)]
    # variables: f (nf), slack s (6) with -s <= E f - w <= s
    contact_A, contact_bu, contact_bl = p.contact_rows
    A = np.vstack([np.hstack([p.equilibrium, -np.eye(6)]), np.hstack([p.equilibrium, np.eye(6)]),
                   np.hstack([contact_A[:, :nf], np.zeros((len(contact_A), 6))])])
    bu = np.concatenate([p.wrench, np.full(6, INFINITE), contact_bu])
    bl = np.concatenate([np.full(6, -INFINITE), p.wrench, contact_bl])
    c = np.r_[np.zeros(nf), weights]
    x = solve(Program(c, A, bu, bl, name="the closest achievable wrench's LP"), solver, fallback,
              **lp_options(solver)).x
    if np.max(x[nf:]) < 1e-6:
        return p
    return replace(p, wrench=p.equilibrium @ x[:nf])


def minimax(problem: StanceProblem, solver: str = "daqp", warm: StanceSolution | None = None,
            smoothing_1_N2: float = 0.0, previous_N: np.ndarray | None = None,
            fallback: str | None = None) -> StanceSolution:
    """The exact minimax of the peak normalised torque (an LP), by ``solver`` (``daqp`` or ``highs``), should
    it fail by ``fallback`` if one is named (said in the solution's ``solver``).

    ``warm``: the previous control step's solution; its active set starts
    the dual active-set solver (same problem structure required).

    ``smoothing_1_N2 > 0`` adds ``smoothing/2 |f - previous|^2`` to the cost
    (a QP, daqp only): many force distributions share nearly the optimal peak and
    the LP's optimum jumps between them as the legs move, which, fed back
    through the body, makes the forces alternate from one control step to the
    next; the proximal term picks the near-optimal one closest to the last
    step (Nair et al.'s one trust-region iteration per step plays that role).
    Should daqp fail on that QP and ``fallback`` be named, the plain LP is
    solved by ``fallback`` and the solution says so.
    """
    lp = problem.minimax_program
    nf = 3 * problem.n
    start = time.perf_counter()
    if smoothing_1_N2 > 0:
        if solver != "daqp":
            raise ValueError("smoothing makes a QP: it needs the daqp solver")
        prev = np.zeros(nf) if previous_N is None else np.ravel(previous_N)
        H = np.zeros((nf + 1, nf + 1))
        H[:nf, :nf] = smoothing_1_N2 * np.eye(nf)
        H[nf, nf] = 1e-9
        c = lp.cost.copy()
        c[:nf] = -smoothing_1_N2 * prev
        qp = replace(lp, cost=c, hessian=H, name="the smoothed stance QP")
        try:
            found = solve(qp, "daqp")
            return StanceSolution(problem, found.x[:nf].reshape(-1, 3), "minimax_smoothed", found.solver,
                                  time.perf_counter() - start, found.iterations, found)
        except SolverError as stalled:
            if fallback is None:
                raise
            found = solve(lp, fallback, **lp_options(fallback))
            return StanceSolution(problem, found.x[:nf].reshape(-1, 3), "minimax", found.solver,
                                  time.perf_counter() - start, found.iterations, found,
                                  fallback_from=f"daqp {stalled.args[1]} on the smoothed QP")
    active = warm.active if warm is not None else None
    found = solve(lp, solver, fallback=fallback, active=active, **lp_options(solver))
    return StanceSolution(problem, found.x[:nf].reshape(-1, 3), "minimax", found.solver,
                          time.perf_counter() - start, found.iterations, found, found.fallback_from)


def minimax_lex(problem: StanceProblem, slack: float = 1e-6, first: StanceSolution | None = None,
                solver: str = "daqp", fallback: str | None = None) -> StanceSolution:
    """Second stage: least squared normalised torque among distributions within ``slack`` of the optimal peak.

    A QP over the forces alone (daqp): ``min |W f + o|^2`` with ``W = diag(1/s) T``,
    ``o = g / s``, subject to equilibrium, the contact constraints and
    ``|T f + g| <= peak* (1 + slack) s``.  ``first``: the minimax already
    solved for this problem (else solved here by ``solver``, ``fallback``).
    """
    p = problem
    first = first or minimax(p, solver, fallback=fallback)
    nf = 3 * p.n
    start = time.perf_counter()
    W = p.torque_map / p.torque_scale_Nm[:, None]
    offset = p.gravity_Nm / p.torque_scale_Nm
    H = 2.0 * W.T @ W + 1e-9 * np.eye(nf)
    f = 2.0 * W.T @ offset
    cap = first.peak * (1.0 + slack) * p.torque_scale_Nm
    contact_A, contact_bu, contact_bl = p.contact_rows
    A = np.vstack([p.equilibrium, p.torque_map, contact_A[:, :nf]])
    bu = np.concatenate([p.wrench, cap - p.gravity_Nm, contact_bu])
    bl = np.concatenate([p.wrench, -cap - p.gravity_Nm, contact_bl])
    found = solve(Program(f, A, bu, bl, n_eq=6, hessian=H, name="the stance problem's second stage (a QP)"),
                  "daqp")
    return StanceSolution(p, found.x.reshape(-1, 3), "minimax_lex", found.solver,
                          first.solve_time_s + time.perf_counter() - start, found.iterations, found,
                          first.fallback_from)


