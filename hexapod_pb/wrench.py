"""Stance-wrench distribution: which ground forces should the stance feet push with?

Problem (Nair et al.'s minimax, generalised).  Stance feet ``i`` at body-frame
positions ``p_i`` push with ground reaction forces ``f_i`` (force *on* the
foot).  The joints of the stance legs must then hold

    tau = T f + g          T = -blockdiag(J_i^T),  g: the legs' own gravity torques

and the robot is in equilibrium when

    sum_i f_i = F,   sum_i p_i x f_i = M        (E f = w)

with ``(F, M)`` the wrench the ground must supply (the weight, plus any body
posture correction).  Nair et al. minimise the peak normalised torque

    min_f  max_j |tau_j| / tau_cont_j    subject to  E f = w

over the friction components of a tripod (normal forces fixed by statics),
with ``scipy.optimize.minimize(method="trust-constr")``.  It is a linear
program in epigraph form:

    min z   subject to  E f = w,  -z s_j <= (T f + g)_j <= z s_j,
                        |f_x|, |f_y| <= friction f_z (friction pyramid), f_z >= f_min (unilateral)

solved exactly here by a dual active-set solver (``daqp``) or HiGHS, for any
number of stance legs, with friction and unilateral constraints Nair et al.
lacks; a second stage picks, among the distributions sharing the optimal
peak, the one of least squared normalised torque; a thermal variant
minimises the peak *predicted temperature* instead.
"""

from __future__ import annotations

import time
import warnings
from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import Mapping

import numpy as np
from scipy.optimize import LinearConstraint, minimize

from thermolimb.model import FirstOrderBank
from thermolimb.optimization.programs import INFINITE, Program, Solution, SolverError, solve

from .legs import leg_statics
from .params import GRAVITY_M_S2, DaisyParams

STRATEGIES = ("vertical_only", "minimax", "minimax_lex", "thermal_aware")  # what distribute() can do


@dataclass(frozen=True)
class StanceProblem:
    """Data of one stance-wrench problem (see the module docstring for the maths)."""

    legs: tuple[int, ...]  # stance legs (indices into LEGS)
    body_p_feet: np.ndarray  # (n, 3) m
    torque_map: np.ndarray  # (3n, 3n): tau = T f + g, stance legs' joints only
    gravity_Nm: np.ndarray  # (3n,) g
    torque_scale_Nm: np.ndarray  # (3n,) normaliser (continuous torque)
    wrench: np.ndarray  # (6,) required (F, M) from the ground, body frame
    friction: float | None = None  # friction coefficient of the pyramid; None: no friction limit (Nair et al.)
    min_normal_N: float | None = None  # unilateral contact; None: no bound (Nair et al.)

    @property
    def n(self) -> int:
        return len(self.legs)

    @cached_property
    def equilibrium(self) -> np.ndarray:
        """``E`` (6 x 3n): net force and net moment about the body origin."""
        E = np.zeros((6, 3 * self.n))
        x, y, z = self.body_p_feet[:, 0], self.body_p_feet[:, 1], self.body_p_feet[:, 2]
        E[0, 0::3] = E[1, 1::3] = E[2, 2::3] = 1.0
        # rows of sum p x f: (y fz - z fy, z fx - x fz, x fy - y fx)
        E[3, 2::3], E[3, 1::3] = y, -z
        E[4, 0::3], E[4, 2::3] = z, -x
        E[5, 1::3], E[5, 0::3] = x, -y
        return E

    @cached_property
    def contact_rows(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Friction-pyramid and unilateral rows ``(A, bu, bl)`` over ``x = (f, z)``: built once per problem and
        shared by every solve and cutting-plane round on it."""
        return _contact_rows(self)

    @cached_property
    def minimax_program(self) -> Program:
        """The epigraph LP of the minimax over ``x = (f, z)``: ``min z`` with the wrench balanced (6 equality
        rows), ``|T f + g| <= z s`` and the contact rows (see the module docstring)."""
        return _epigraph(self)

    @classmethod
    def from_configuration(cls, params: DaisyParams, q: np.ndarray, legs, payload_kg: float = 0.0,
                           wrench: np.ndarray | None = None, include_leg_gravity: bool = True,
                           friction: float | None = None, min_normal_N: float | None = None,
                           world_R_body: np.ndarray | None = None) -> "StanceProblem":
        """Build the problem for joint angles ``q`` (18,) and stance legs.

        Default wrench: hold the whole robot and payload up (gravity in the
        body frame, from ``world_R_body``), no net moment about the body
        origin (the centre of mass).
        """
        statics = {int(i): leg_statics(params, int(i), q[3 * int(i) : 3 * int(i) + 3], world_R_body) for i in legs}
        return cls.from_statics(params, statics, payload_kg, wrench, include_leg_gravity, friction, min_normal_N,
                                world_R_body)

    @classmethod
    def from_statics(cls, params: DaisyParams, statics: dict, payload_kg: float = 0.0,
                     wrench: np.ndarray | None = None, include_leg_gravity: bool = True,
                     friction: float | None = None, min_normal_N: float | None = None,
                     world_R_body: np.ndarray | None = None) -> "StanceProblem":
        """The problem from each stance leg's :class:`~hexapod_pb.legs.LegStatics` (computed once per step)."""
        legs = tuple(statics)
        if len(legs) < 3:
            raise ValueError(f"a static stance needs at least 3 feet on the ground, got {len(legs)}")
        if wrench is None:
            R = np.eye(3) if world_R_body is None else world_R_body
            weight = (params.robot_mass_kg + payload_kg) * GRAVITY_M_S2
            wrench = np.concatenate([R.T @ np.array([0.0, 0.0, weight]), np.zeros(3)])
        T = np.zeros((3 * len(legs), 3 * len(legs)))
        for k, i in enumerate(legs):
            T[3 * k : 3 * k + 3, 3 * k : 3 * k + 3] = -statics[i].jacobian.T
        grav = [statics[i].gravity_Nm if include_leg_gravity else np.zeros(3) for i in legs]
        feet = np.array([statics[i].foot_m for i in legs])
        scale = np.concatenate([params.continuous_effort_Nm[3 * i : 3 * i + 3] for i in legs])
        return cls(legs, feet, T, np.concatenate(grav), scale, np.asarray(wrench, float), friction, min_normal_N)

    def torques(self, f: np.ndarray) -> np.ndarray:
        return self.torque_map @ np.ravel(f) + self.gravity_Nm

    def normalised(self, f: np.ndarray) -> np.ndarray:
        return np.abs(self.torques(f)) / self.torque_scale_Nm


@dataclass(frozen=True)
class StanceSolution:
    """A distribution of ground forces and what it costs; ``residuals`` certify it.

    ``strategy`` says how the forces were chosen, ``solver`` what produced them (``"daqp"``, ``"highs"``,
    ``"trust-constr"``, ``"closed form"``) and ``fallback_from``, when the solver named first failed, what
    it reported; a blend keeps each strategy's solution in ``parts``.
    """

    problem: StanceProblem
    forces_N: np.ndarray  # (n, 3) on each stance foot, body frame
    strategy: str
    solver: str
    solve_time_s: float
    iterations: int = 0
    program: Solution | None = field(default=None, repr=False)  # the solved program, with its certificate
    fallback_from: str | None = None
    parts: tuple["StanceSolution", ...] = field(default=(), repr=False)

    @property
    def label(self) -> str:
        """``"minimax by daqp"``, ``"minimax by highs (daqp stalled, exit flag -2)"``; a blend's parts, joined."""
        if self.parts:
            return "; ".join(part.label for part in self.parts)
        fallback = f" ({self.fallback_from})" if self.fallback_from else ""
        return f"{self.strategy} by {self.solver}{fallback}"

    @property
    def fell_back(self) -> bool:
        """Whether a fallback solver produced this solution (or one of a blend's parts)."""
        return self.fallback_from is not None or any(part.fell_back for part in self.parts)

    @property
    def active(self) -> np.ndarray | None:
        """The solved program's active set, to warm-start the next control step's."""
        return None if self.program is None else self.program.active

    @property
    def torques_Nm(self) -> np.ndarray:
        return self.problem.torques(self.forces_N)

    @property
    def peak(self) -> float:
        """Peak normalised torque ``max_j |tau_j| / tau_cont_j``."""
        return float(np.max(self.problem.normalised(self.forces_N)))

    def residuals(self) -> dict[str, float]:
        """Equilibrium error (N, N m), friction-cone and unilateral violations (N); for a solved program also
        its certificate (:meth:`~thermolimb.optimization.programs.Program.residuals`: bounds, stationarity,
        complementarity, duality gap)."""
        p = self.problem
        f = self.forces_N
        out = {"equilibrium": float(np.max(np.abs(p.equilibrium @ f.ravel() - p.wrench)))}
        if p.friction is not None:
            out["friction"] = float(max(0.0, np.max(np.abs(f[:, :2]) - p.friction * f[:, 2:3])))
        if p.min_normal_N is not None:
            out["unilateral"] = float(max(0.0, np.max(p.min_normal_N - f[:, 2])))
        if self.program is not None:
            out.update(self.program.residuals)
        return out


# ---------------------------------------------------------------- baseline


def vertical_only(problem: StanceProblem) -> StanceSolution:
    """HEBI's stock distribution: vertical forces sharing the load so that roll and pitch moments balance.

    The least-norm normal forces meeting the vertical force and the roll and
    pitch moments (exact for a tripod).  Any horizontal force the body asks
    for (propulsion, drift correction) is shared equally, so that this
    baseline walks; the yaw moment is not controlled.
    """
    start = time.perf_counter()
    p = problem
    A = np.vstack([np.ones(p.n), p.body_p_feet[:, 1], -p.body_p_feet[:, 0]])
    b = np.array([p.wrench[2], p.wrench[3], p.wrench[4]])
    normal = np.linalg.lstsq(A, b, rcond=None)[0]
    f = np.zeros((p.n, 3))
    f[:, 2] = normal
    f[:, :2] = p.wrench[:2] / p.n
    return StanceSolution(p, f, "vertical_only", "closed form", time.perf_counter() - start)


# ----------------------------------------------------------- Nair et al.'s way


def nair_trust_constr(problem: StanceProblem, zero_hessian: bool = True, x0: np.ndarray | None = None,
                      maxiter: int = 500) -> StanceSolution:
    """Nair et al.'s method: normal forces from statics, trust-constr over the friction components of a tripod.

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
        # the quasi-Newton update warns that the cost is piecewise linear: that is why Nair et al. zeroed the Hessian
        warnings.simplefilter("ignore", UserWarning)
        result = minimize(cost, np.zeros(6) if x0 is None else x0, method="trust-constr",
                          constraints=[LinearConstraint(A, b, b)], options={"maxiter": maxiter, "verbose": 0}, **kwargs)
    return StanceSolution(p, forces(result.x), "nair_trust_constr", "trust-constr", time.perf_counter() - start,
                          int(result.nit))


# ------------------------------------------------------------ exact minimax


def _epigraph(problem: StanceProblem) -> Program:
    """The minimax LP over ``x = (f, z)``; the first 6 rows are equalities."""
    p = problem
    nf = 3 * p.n
    s = p.torque_scale_Nm
    contact = p.friction is not None or p.min_normal_N is not None
    contact_A, contact_bu, contact_bl = p.contact_rows if contact else (None, None, None)
    m = 6 + 2 * nf + (len(contact_A) if contact else 0)
    A = np.zeros((m, nf + 1))
    A[:6, :nf] = p.equilibrium
    A[6 : 6 + nf, :nf] = p.torque_map  # T f + g - z s <= 0
    A[6 : 6 + nf, nf] = -s
    A[6 + nf : 6 + 2 * nf, :nf] = p.torque_map  # T f + g + z s >= 0
    A[6 + nf : 6 + 2 * nf, nf] = s
    bu = np.empty(m)
    bl = np.empty(m)
    bu[:6] = bl[:6] = p.wrench
    bu[6 : 6 + nf] = -p.gravity_Nm
    bl[6 : 6 + nf] = -INFINITE
    bu[6 + nf : 6 + 2 * nf] = INFINITE
    bl[6 + nf : 6 + 2 * nf] = -p.gravity_Nm
    if contact:
        A[6 + 2 * nf :] = contact_A
        bu[6 + 2 * nf :] = contact_bu
        bl[6 + 2 * nf :] = contact_bl
    c = np.zeros(nf + 1)
    c[-1] = 1.0
    return Program(c, A, bu, bl, n_eq=6, name="the stance LP")


# daqp's proximal iterations for an LP (it has no Hessian to regularise)
DAQP_LP_OPTIONS = {"eps_prox": 1e-6}


def _options(solver: str) -> dict:
    return DAQP_LP_OPTIONS if solver == "daqp" else {}


MOMENT_ARM_M = 0.3  # weights moment errors against force errors in the closest achievable wrench


def closest_achievable(problem: StanceProblem, solver: str = "daqp", fallback: str | None = None) -> StanceProblem:
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
              **_options(solver)).x
    if np.max(x[nf:]) < 1e-6:
        return p
    return replace(p, wrench=p.equilibrium @ x[:nf])


def minimax(problem: StanceProblem, solver: str = "daqp", warm: StanceSolution | None = None,
            smoothing_1_N2: float = 0.0, previous_N: np.ndarray | None = None,
            fallback: str | None = None) -> StanceSolution:
    """The exact minimax of the peak normalised torque (an LP), by ``solver`` (``daqp`` or ``highs``), should it
    fail by ``fallback`` if one is named (said in the solution's ``solver``).

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
            found = solve(lp, fallback, **_options(fallback))
            return StanceSolution(problem, found.x[:nf].reshape(-1, 3), "minimax", found.solver,
                                  time.perf_counter() - start, found.iterations, found,
                                  fallback_from=f"daqp {stalled.args[1]} on the smoothed QP")
    active = warm.active if warm is not None else None
    found = solve(lp, solver, fallback=fallback, active=active, **_options(solver))
    return StanceSolution(problem, found.x[:nf].reshape(-1, 3), "minimax", found.solver, time.perf_counter() - start,
                          found.iterations, found, found.fallback_from)


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
    found = solve(Program(f, A, bu, bl, n_eq=6, hessian=H, name="the stance problem's second stage (a QP)"), "daqp")
    return StanceSolution(p, found.x.reshape(-1, 3), "minimax_lex", found.solver,
                          first.solve_time_s + time.perf_counter() - start, found.iterations, found,
                          first.fallback_from)


# ------------------------------------------------------------ thermal-aware


def thermal_minimax(problem: StanceProblem, bank: FirstOrderBank, temperature_C: np.ndarray, horizon_s: float,
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
    # what every round shares: the wrench balance, the contact rows and the torques within 3x their scale (a trust
    # region for the cuts)
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
        found = solve(Program(c, A, bu, bl, n_eq=6, name="the thermal minimax's cutting-plane LP"), solver, fallback,
                      **_options(solver))
        fell_back |= {found.fallback_from} - {None}
        x = found.x
        sol = StanceSolution(p, x[:nf].reshape(-1, 3), "thermal_aware", found.solver, 0.0, rounds, found)
        tau = p.torques(sol.forces_N)
        true_peak = float(np.max(a + b * tau + cq * tau**2))
        if true_peak - x[-1] <= tol_K:
            break
    return replace(sol, solve_time_s=time.perf_counter() - start, iterations=rounds,
                   fallback_from="; ".join(sorted(fell_back)) or None)


def distribute(problem: StanceProblem, strategy: str | Mapping[str, float], warm: StanceSolution | None = None,
               bank: FirstOrderBank | None = None, temperature_C: np.ndarray | None = None, horizon_s: float = 20.0,
               smoothing_1_N2: float = 0.0, solver: str = "daqp", fallback: str | None = None) -> StanceSolution:
    """Stance forces by ``strategy`` (one of :data:`STRATEGIES`, or ``{name: weight}`` to blend them: a convex
    combination of balanced distributions is balanced), for the nearest wrench the contacts can supply.

    ``warm``: the previous control step's solution (its forces smooth the
    minimax, its active set starts the solver); ``bank``, ``temperature_C``
    (all 18 joints) and ``horizon_s``: what ``thermal_aware`` predicts with.
    Every program is solved by ``solver``, and by ``fallback`` only when it is
    named and ``solver`` fails: the solution's ``solver`` and ``fallback_from``
    say what ran.  Each program is solved once per call, also in a blend (the
    closest wrench once; the torque minimax once, shared by ``minimax``,
    ``minimax_lex`` and ``thermal_aware``'s first point).
    """
    weights = {strategy: 1.0} if isinstance(strategy, str) else {k: float(v) for k, v in strategy.items() if v > 0}
    unknown = [k for k in weights if k not in STRATEGIES]
    if unknown or not weights:
        raise ValueError(f"unknown strategy {unknown or strategy!r}; expected one of {', '.join(STRATEGIES)}")
    if "thermal_aware" in weights and (bank is None or temperature_C is None):
        raise ValueError("the thermal_aware strategy needs identified models (bank) and the joints' temperatures")
    achievable = problem if set(weights) == {"vertical_only"} else closest_achievable(problem, solver, fallback)
    plain: list[StanceSolution] = []  # the torque minimax of `achievable`, solved at most once

    def torque_minimax() -> StanceSolution:
        if not plain:
            plain.append(minimax(achievable, solver, fallback=fallback))
        return plain[0]

    def one(name: str) -> StanceSolution:
        if name == "vertical_only":
            return vertical_only(problem)
        if name == "minimax":
            if smoothing_1_N2 <= 0:
                return torque_minimax()
            previous = np.zeros((achievable.n, 3))
            if warm is not None:
                last = dict(zip(warm.problem.legs, warm.forces_N))
                previous = np.array([last.get(i, np.zeros(3)) for i in achievable.legs])
            return minimax(achievable, solver, smoothing_1_N2=smoothing_1_N2, previous_N=previous, fallback=fallback)
        if name == "minimax_lex":
            return minimax_lex(achievable, first=torque_minimax())
        joints = np.concatenate([np.arange(3 * i, 3 * i + 3) for i in achievable.legs])
        return thermal_minimax(achievable, bank.subset(joints), np.asarray(temperature_C)[joints], horizon_s,
                               first=torque_minimax(), solver=solver, fallback=fallback)

    parts = [(w, one(name)) for name, w in weights.items()]
    if len(parts) == 1:
        return parts[0][1]
    total = sum(w for w, _ in parts)
    first = parts[0][1]
    return StanceSolution(first.problem, sum(w / total * part.forces_N for w, part in parts), "blend",
                          ", ".join(sorted({part.solver for _, part in parts})),
                          sum(part.solve_time_s for _, part in parts), parts=tuple(part for _, part in parts))


def _contact_rows(p: StanceProblem):
    """Friction pyramid ``|f_x|, |f_y| <= friction f_z`` and unilateral ``f_z >= f_min`` rows over ``x = (f, z)``."""
    nf = 3 * p.n
    blocks, bu, bl = [], [], []
    if p.friction is not None:
        rows = np.zeros((4 * p.n, nf + 1))
        k = np.repeat(np.arange(p.n), 4)
        axis = np.tile([0, 0, 1, 1], p.n)
        rows[np.arange(4 * p.n), 3 * k + axis] = np.tile([1.0, -1.0, 1.0, -1.0], p.n)
        rows[np.arange(4 * p.n), 3 * k + 2] = -p.friction
        blocks.append(rows)
        bu.append(np.zeros(4 * p.n))
        bl.append(np.full(4 * p.n, -INFINITE))
    if p.min_normal_N is not None:
        rows = np.zeros((p.n, nf + 1))
        rows[np.arange(p.n), 3 * np.arange(p.n) + 2] = 1.0
        blocks.append(rows)
        bu.append(np.full(p.n, INFINITE))
        bl.append(np.full(p.n, p.min_normal_N))
    if not blocks:
        return np.zeros((0, nf + 1)), np.zeros(0), np.zeros(0)
    return np.vstack(blocks), np.concatenate(bu), np.concatenate(bl)
