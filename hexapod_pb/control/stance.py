"""The stance-wrench problem as data: stance feet, the torques their forces make, the wrench the ground must
supply, and the contact constraints (``StanceProblem``); a solution that reports what solved it and how close
to the optimum it is (``StanceSolution``); HEBI's stock vertical-only distribution, and the minimax LP's
epigraph form the exact solvers take (:mod:`.minimax`).

Stance-wrench distribution: which ground forces should the stance feet push with?

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
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from thermolimb.optimization.programs import INFINITE, Program, Solution

from ..model.legs import leg_statics
from ..params import GRAVITY_M_S2, DaisyParams


@dataclass(frozen=True)
class StanceProblem:
    """Data of one stance-wrench problem (see the module docstring for the maths)."""

    legs: tuple[int, ...]  # stance legs (indices into LEGS)
    body_p_feet: np.ndarray  # (n, 3) m
    torque_map: np.ndarray  # (3n, 3n): tau = T f + g, stance legs' joints only
    gravity_Nm: np.ndarray  # (3n,) g
    torque_scale_Nm: np.ndarray  # (3n,) normaliser (continuous torque)
    wrench: np.ndarray  # (6,) required (F, M) from the ground, body frame
    # friction coefficient of the pyramid; None: no friction limit (Nair et al.)
    friction: float | None = None
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
        """Friction-pyramid and unilateral rows ``(A, bu, bl)`` over ``x = (f, z)``: built once per problem
        and shared by every solve and cutting-plane round on it."""
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
        statics = {
            int(i): leg_statics(params, int(i), q[3 * int(i) : 3 * int(i) + 3], world_R_body) for i in legs
        }
        return cls.from_statics(params, statics, payload_kg, wrench, include_leg_gravity, friction,
                                min_normal_N, world_R_body)

    @classmethod
    def from_statics(cls, params: DaisyParams, statics: dict, payload_kg: float = 0.0,
                     wrench: np.ndarray | None = None, include_leg_gravity: bool = True,
                     friction: float | None = None, min_normal_N: float | None = None,
                     world_R_body: np.ndarray | None = None) -> "StanceProblem":
        """The problem from each stance leg's :class:`~hexapod_pb.legs.LegStatics` (computed once per
        step)."""
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
        return cls(legs, feet, T, np.concatenate(grav), scale, np.asarray(wrench, float), friction,
                   min_normal_N)

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
        """``"minimax by daqp"``, ``"minimax by highs (daqp stalled, exit flag -2)"``; a blend's parts,
        joined."""
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


# ------------------------------------------------------------ the minimax LP


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


def _contact_rows(p: StanceProblem):
    """Friction pyramid ``|f_x|, |f_y| <= friction f_z`` and unilateral ``f_z >= f_min`` rows over
    ``x = (f, z)``."""
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
