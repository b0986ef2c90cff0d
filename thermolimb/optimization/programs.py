"""Linear and quadratic programs of the robots' controllers, solved by a named solver, with their
certificates.

Both robots solve small dense programs every control step: the hexapod's
stance-wrench LPs and QPs (``hexapod_pb.wrench``), the humanoid's thermal IK
QPs (``humanoid_pb.ik.fast_ik``).  Here they have one form,

    min  1/2 x'Hx + c'x   subject to   lower <= A x <= upper,   the first ``n_eq`` rows equalities,
                                       and bounds on the leading variables (daqp's simple bounds)

(``H = 0``: a linear program), one solver call and one certificate:

* the caller names the solver: ``"daqp"`` (a dual active-set method, microseconds
  on these sizes, warm-startable) or ``"highs"`` (``scipy.optimize.linprog``, LPs
  only); a fallback from one to the other happens only when asked for, and the
  solution says which solver produced it and why the named one did not
  (``solver="highs"``, ``fallback_from="daqp stalled, exit flag -2"``; its
  ``label``: ``"highs (daqp stalled, exit flag -2)"``);
* every solution carries its residuals: the worst bound violation, and with
  multipliers (LPs and QPs by daqp, LPs by HiGHS) the KKT stationarity,
  complementarity and the duality gap ``primal - dual``.

Multipliers follow daqp's sign convention: ``lam_i > 0`` on a row at its upper
bound, ``< 0`` at its lower bound, so that ``H x + c + A' lam = 0``.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from functools import cached_property

import numpy as np

INFINITE = 1e30  # a bound at or beyond this is no bound (daqp's convention)
EQUALITY = 5  # daqp row sense: active and immutable
ACTIVE = 1  # daqp row sense: active at the start (a warm start)
SOLVERS = ("daqp", "highs")


@dataclass(frozen=True)
class Program:
    """``min 1/2 x'Hx + c'x`` subject to ``lower <= A x <= upper``; the first ``n_eq`` rows are equalities.

    ``hessian`` ``None`` makes it a linear program.  ``bounds`` ``(upper,
    lower)`` of length ``k`` bound the first ``k`` variables directly.
    ``name`` says what it is in error messages (``"the stance LP"``).
    """

    cost: np.ndarray
    A: np.ndarray
    upper: np.ndarray
    lower: np.ndarray
    n_eq: int = 0
    hessian: np.ndarray | None = field(default=None, repr=False)
    bounds: tuple[np.ndarray, np.ndarray] | None = field(default=None, repr=False)
    name: str = "the program"

    def __post_init__(self):
        m, n = self.A.shape
        if self.cost.shape != (n,) or self.upper.shape != (m,) or self.lower.shape != (m,):
            raise ValueError(f"{self.name}: cost {self.cost.shape}, A "
                             f"{self.A.shape}, upper {self.upper.shape} and "
                             f"lower {self.lower.shape} do not fit together "
                             "(n variables, m rows: (n,), (m, n), (m,))")

    @property
    def n_bounded(self) -> int:
        """How many leading variables ``bounds`` bounds directly."""
        return 0 if self.bounds is None else len(self.bounds[0])

    def all_rows(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(A, upper, lower)`` with the direct bounds as rows of their own, first (daqp's order)."""
        if self.bounds is None:
            return self.A, self.upper, self.lower
        k = self.n_bounded
        eye = np.eye(k, len(self.cost))
        return (np.vstack([eye, self.A]), np.concatenate([self.bounds[0], self.upper]),
                np.concatenate([self.bounds[1], self.lower]))

    @property
    def is_linear(self) -> bool:
        return self.hessian is None

    def objective(self, x: np.ndarray) -> float:
        value = float(self.cost @ x)
        return value if self.hessian is None else value + 0.5 * float(x @ self.hessian @ x)

    def residuals(self, x: np.ndarray, duals: np.ndarray | None) -> dict[str, float]:
        """``bounds``: worst violation of a row's bounds; with multipliers (one per row of :meth:`all_rows`)
        also ``stationarity`` (``|Hx + c + A'lam|``), ``complementarity`` (a multiplier times its row's
        distance from its bound) and ``duality_gap`` (primal minus dual objective; 0 at an optimum)."""
        A, upper, lower = self.all_rows()
        row = A @ x
        out = {"bounds": float(max(0.0, np.max(row - upper, initial=0.0), np.max(lower - row, initial=0.0)))}
        if duals is None:
            return out
        lam = np.asarray(duals, float)
        gradient = self.cost if self.hessian is None else self.hessian @ x + self.cost
        out["stationarity"] = float(np.max(np.abs(gradient + A.T @ lam), initial=0.0))
        bound = np.where(lam > 0, upper, lower)
        inequality = np.ones(len(upper), bool)
        inequality[self.n_bounded : self.n_bounded + self.n_eq] = False
        gaps = np.abs(lam[inequality]) * np.abs(row[inequality] - bound[inequality])
        out["complementarity"] = float(np.max(gaps, initial=0.0))
        # the dual function at lam: min_x L(x, lam) = -1/2 x'Hx - bound'lam at a stationary x
        quadratic = 0.0 if self.hessian is None else 0.5 * float(x @ self.hessian @ x)
        dual = -quadratic - float(np.sum(np.where(lam != 0.0, lam * bound, 0.0)))
        out["duality_gap"] = self.objective(x) - dual
        return out


@dataclass(frozen=True)
class Solution:
    """A program's solution: ``x``, which solver found it (and, after a fallback, why the one named first did
    not), its iterations, multipliers and residuals."""

    x: np.ndarray
    solver: str
    iterations: int
    duals: np.ndarray | None = field(repr=False)
    program: Program = field(repr=False)
    fallback_from: str | None = None  # the solver named first and what it reported, when a fallback solved

    @property
    def label(self) -> str:
        """``"daqp"``, or after a fallback ``"highs (daqp stalled, exit flag -2)"``."""
        return self.solver if self.fallback_from is None else f"{self.solver} ({self.fallback_from})"

    @cached_property
    def residuals(self) -> dict[str, float]:
        """:meth:`Program.residuals` at this solution (computed when first asked: a control step need not)."""
        return self.program.residuals(self.x, self.duals)

    @property
    def active(self) -> np.ndarray | None:
        """Rows with a non-zero multiplier: the active set, to warm-start the next solve."""
        return None if self.duals is None else np.abs(self.duals) > 0


class SolverError(RuntimeError):
    """A program the named solver could not solve (infeasible, or the solver stalled)."""


def senses(program: Program, active: np.ndarray | None = None) -> np.ndarray:
    """daqp's row senses (direct bounds first): equalities immutable, the rows ``active`` marks (a previous
    solution's active set) active."""
    k = program.n_bounded
    out = np.zeros(k + len(program.upper), dtype=np.intc)
    if active is not None and active.shape == out.shape:
        out[active] = ACTIVE
    out[k : k + program.n_eq] = EQUALITY
    return out


def solve(program: Program, solver: str = "daqp", fallback: str | None = None,
          active: np.ndarray | None = None, **options) -> Solution:
    """Solve ``program`` by ``solver``; should it fail and ``fallback`` be named, by that, and the solution's
    ``fallback_from`` says why.

    ``active``: a previous solution's :attr:`Solution.active` (daqp warm start);
    ``options`` go to daqp (e.g. ``eps_prox`` for an LP's proximal iterations).
    Raises :class:`SolverError` naming the program and each solver's exit.
    """
    for name in (solver, fallback):
        if name is not None and name not in SOLVERS:
            raise ValueError(f"unknown solver {name!r}; expected one of {', '.join(SOLVERS)}")
    try:
        return _SOLVE[solver](program, active, options)
    except SolverError as failed:
        if fallback is None:
            raise
        try:
            found = _SOLVE[fallback](program, None, {})
        except SolverError as also:
            raise SolverError(f"{failed}; {also}") from None
        return replace(found, fallback_from=f"{solver} {failed.args[1]}")


def _daqp(program: Program, active, options) -> Solution:
    import daqp  # the controllers' solver: imported with them, not with the core

    H = _zero_hessian(len(program.cost)) if program.hessian is None else program.hessian
    upper, lower = program.upper, program.lower
    if program.bounds is not None:
        upper, lower = np.concatenate([program.bounds[0], upper]), np.concatenate([program.bounds[1], lower])
    x, _, flag, info = daqp.solve(H, program.cost, program.A, upper, lower, senses(program, active),
                                  **options)
    if flag < 1:
        raise SolverError(
            f"daqp could not solve {program.name} (exit flag {flag})", f"stalled, exit flag {flag}"
        )
    return Solution(x, "daqp", int(info["iterations"]), np.asarray(info["lam"], float), program)


_ZERO_HESSIANS: dict[int, np.ndarray] = {}


def _zero_hessian(n: int) -> np.ndarray:
    """One zero matrix per size, reused: an LP's Hessian (daqp regularises it and does not write to it)."""
    if n not in _ZERO_HESSIANS:
        _ZERO_HESSIANS[n] = np.zeros((n, n))
    return _ZERO_HESSIANS[n]


def _highs(program: Program, active, options) -> Solution:
    from scipy.optimize import linprog

    if not program.is_linear:
        raise ValueError(f"{program.name} is a QP; HiGHS here solves linear programs only (use daqp)")
    if program.bounds is not None:
        raise ValueError(f"{program.name} has direct bounds (daqp's form); give them as rows for HiGHS")
    k = program.n_eq
    rows = np.arange(len(program.upper)) >= k
    upper = rows & (program.upper < INFINITE / 2)
    lower = rows & (program.lower > -INFINITE / 2)
    res = linprog(program.cost, A_ub=np.vstack([program.A[upper], -program.A[lower]]),
                  b_ub=np.concatenate([program.upper[upper], -program.lower[lower]]),
                  A_eq=program.A[:k], b_eq=program.upper[:k], bounds=[(None, None)] * len(program.cost),
                  method="highs")
    if res.status != 0:
        raise SolverError(f"HiGHS could not solve {program.name}: {res.message}", f"failed: {res.message}")
    # scipy's marginals are d(objective)/d(bound), <= 0 on A_ub rows: in daqp's convention lam = -marginal on
    # an upper row, +marginal on a lower row (written as -A x <= -lower), -marginal on an equality
    lam = np.zeros(len(program.upper))
    lam[:k] = -res.eqlin.marginals
    n_upper = int(upper.sum())
    lam[upper] = -res.ineqlin.marginals[:n_upper]
    lam[lower] += res.ineqlin.marginals[n_upper:]
    return Solution(res.x, "highs", int(res.nit), lam, program)


_SOLVE = {"daqp": _daqp, "highs": _highs}
