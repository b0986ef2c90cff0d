"""The fast thermal IK: sequential quadratic programs with analytic derivatives and every constraint.

Decision variables at each iteration: a configuration step ``dq`` (tangent
space, 29), joint torques ``Gamma`` (23) and sole wrenches ``F`` (6 per
contact, sole frames).  Constraints, linearised at the current point:

* contacts held exactly: ``J_c dq = -log(M_c^-1 M(q))`` for every sole in
  contact (then a Newton correction after each step);
* static equilibrium ``S_a' Gamma + J_c' F = g(q)``, linearised with
  Pinocchio's analytic derivative of ``g(q) - J_c(q)' F``;
* unilateral normals, friction pyramids, centre of pressure inside each sole
  (hence the centre of mass over the support polygon), yaw friction;
* joint limits, actuator effort limits (rods through Eq. 24);
* in single support, the free sole at least 5 cm off the ground.

The objective -- the thermal potential (Eq. 26) or minimum effort -- is a sum
of squared residuals of the efforts, handled by Gauss-Newton; a step is kept
only if it lowers the *exact* optimum at the new configuration (a convex
problem in ``(Gamma, F)`` at fixed ``q``), with a trust region on ``dq``.
Unlike Jorgensen et al.'s method, ``Gamma`` is any torque that balances the robot
within its contact constraints, not only the dynamically consistent one.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
import pinocchio as pin

from thermolimb.optimization.programs import INFINITE, Program, SolverError, solve

from ..constants import FOOT_SIDE, JOINTS, SIDES, leg_joint, mode_feet
from ..model.actuation import effort_limits, effort_matrix
from ..model.statics import WholeBody
from .descent import contact_drift
from .like_for_like import gauss_newton, min_norm_balance, sole_forces

MU = 0.6  # friction pyramid
MU_YAW_M = 0.05  # yaw friction moment per newton of normal force
MIN_NORMAL_N = 20.0
COP_MARGIN_M = 0.015
SWING_CLEARANCE_M = 0.05
MAX_STEP_RAD = 0.2  # trust region cap: at 0.3 a third of the steps on the benchmark's starts were rejected


@dataclass(frozen=True)
class FastIKResult:
    """What the fast thermal IK found: the configuration, the balancing torques and sole wrenches it chose
    with it (its free choice, not Eq. 23's), the potential they give, and how it got there."""

    mode: str
    q: np.ndarray
    potential: float  # with its own torques and wrenches (score q under Eq. 23 with descent.potential_of)
    torques_Nm: np.ndarray  # balancing joint torques at q
    contact_wrenches: np.ndarray  # (feet, 6) per sole, sole frame
    iterations: int
    wall_s: float
    history: list[float] = field(default_factory=list)
    contact_drift_m: float = 0.0  # largest sole displacement from the start (m)
    solver: str = "daqp"  # what solved its QPs
    # each QP the solver could not solve (infeasible at that trust region, or stalled): the step was rejected
    # and the trust region halved; the solver's own words
    qp_failures: tuple[str, ...] = ()


class FastThermalIK:
    """Reusable solver for one robot (caches the model's constant data).

    ``solver`` names the QP solver (daqp: HiGHS here solves linear programs only, so a QP has no fallback);
    a QP it cannot solve rejects that step, and the result lists each failure in ``qp_failures``.
    """

    def __init__(self, body: WholeBody, solver: str = "daqp"):
        if solver != "daqp":
            raise ValueError(f"the thermal IK solves quadratic programs: its solver is daqp, got {solver!r}")
        self.solver = solver
        self.failures: list[str] = []  # the current solve's QP failures
        self.body = body
        p = body.params
        # the URDF's (like-for-like mode)
        self.robot_limits_q = np.array([body.params.limits(j) for j in JOINTS])
        self.limits_q = self.robot_limits_q.copy()
        # the IK's working range: knees never straight (singular, and torque-free in a rigid model)
        for side in SIDES:
            k = JOINTS.index(leg_joint(side, "knee"))
            self.limits_q[k, 0] = max(self.limits_q[k, 0], p.knee_min_rad)
        self.half_sole = np.array(p.sole_m) / 2.0 - COP_MARGIN_M
        self.actuator_limits = None
        self._E = (None, None)  # (q's bytes, its effort matrix): each configuration's is needed twice
        self._wrench_cache = {}

    def _effort_matrix(self, q: np.ndarray) -> np.ndarray:
        key = q.tobytes()
        if self._E[0] != key:
            self._E = (key, effort_matrix(self.body.rods, self.body.joint_angles(q)))
        return self._E[1]

    # ----------------------------------------------------------- linear algebra
    def _wrench_rows(self, k: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Rows over ``k`` sole wrenches ``(fx, fy, fz, mx, my, mz)`` with bl <= R w <= bu (built once per
        k)."""
        if k not in self._wrench_cache:
            self._wrench_cache[k] = self._build_wrench_rows(k)
        return self._wrench_cache[k]

    def _build_wrench_rows(self, k: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        lx, ly = self.half_sole
        rows = [
            [0, 0, 1, 0, 0, 0],  # fz >= f_min
            [1, 0, -MU, 0, 0, 0], [-1, 0, -MU, 0, 0, 0],  # |fx| <= mu fz
            [0, 1, -MU, 0, 0, 0], [0, -1, -MU, 0, 0, 0],  # |fy| <= mu fz
            # |mx| <= (w/2) fz: centre of pressure across the sole
            [0, 0, -ly, 1, 0, 0], [0, 0, -ly, -1, 0, 0],
            [0, 0, -lx, 0, 1, 0], [0, 0, -lx, 0, -1, 0],  # |my| <= (l/2) fz: and along it
            [0, 0, -MU_YAW_M, 0, 0, 1], [0, 0, -MU_YAW_M, 0, 0, -1],
        ]
        R = np.array(rows, float)
        bu = np.r_[INFINITE, np.zeros(len(rows) - 1)]
        bl = np.r_[MIN_NORMAL_N, np.full(len(rows) - 1, -INFINITE)]
        blocks = np.zeros((len(rows) * k, 6 * k))
        for i in range(k):
            blocks[len(rows) * i : len(rows) * (i + 1), 6 * i : 6 * i + 6] = R
        return blocks, np.tile(bu, k), np.tile(bl, k)

    def _contact_error(self, q: np.ndarray, targets: dict) -> np.ndarray:
        poses = self.body.sole_poses(q)
        return np.concatenate([pin.log6(targets[s].inverse() * poses[s]).vector for s in targets])

    def _project_contacts(self, q: np.ndarray, mode: str, targets: dict, iterations: int = 3) -> np.ndarray:
        """Newton steps on the contact pose error: the contacts stay exactly where they were."""
        for _ in range(iterations):
            e = self._contact_error(q, targets)
            if np.max(np.abs(e)) < 1e-10:
                break
            Jc = self.body.contact_jacobian(q, mode)  # full row rank: the least-norm step through J J'
            q = pin.integrate(self.body.model, q, -Jc.T @ np.linalg.solve(Jc @ Jc.T, e))
        return q

    # -------------------------------------------------------------------- QPs
    @staticmethod
    def _objective_model(E, objective, Gamma):
        """Newton model of the objective in ``Gamma`` (its Hessian in the efforts is diagonal and >= 0),
        scaled."""
        value, gradient, hessian = objective.newton(E @ Gamma)
        scale = 1.0 / max(value, 1e-12)
        H_gamma = E.T @ ((scale * hessian)[:, None] * E)
        return H_gamma, E.T @ (scale * gradient) - H_gamma @ Gamma

    def _static_rows(self, E, k: int, n_before: int):
        """Rows over ``(..., Gamma, F)`` (``n_before`` leading variables): sole wrench cones and effort
        limits."""
        na, nf = len(JOINTS), 6 * k
        W, wbu, wbl = self._wrench_rows(k)
        lim = self.actuator_limits
        A = np.vstack([np.hstack([np.zeros((len(W), n_before + na)), W]),
                       np.hstack([np.zeros((na, n_before)), E, np.zeros((na, nf))])])
        return A, np.concatenate([wbu, lim]), np.concatenate([wbl, -lim])

    def _solve_qp(self, H, f, blocks, bounds=None):
        """daqp over ``blocks`` of ``(A, upper, lower, equality)`` and simple ``bounds`` ``(upper, lower)`` on
        the leading variables; None if infeasible."""
        blocks = sorted(blocks, key=lambda b: not b[3])  # equalities first
        n_eq = sum(len(b[1]) for b in blocks if b[3])
        program = Program(f, np.vstack([b[0] for b in blocks]), np.concatenate([b[1] for b in blocks]),
                          np.concatenate([b[2] for b in blocks]), n_eq=n_eq, hessian=H, bounds=bounds,
                          name="the thermal IK's QP")
        try:
            return solve(program, self.solver).x
        except SolverError as failed:  # said in the result's qp_failures; the caller rejects the step
            self.failures.append(str(failed))
            return None

    def _inner_qp(self, q, E, mode, objective, Gamma):
        """The exact problem at fixed ``q``: best ``(Gamma, F)`` of the Newton model, balanced, in the
        cones."""
        body = self.body
        na, k = len(JOINTS), len(mode_feet(mode))
        nf = 6 * k
        H = 1e-9 * np.eye(na + nf)
        f = np.zeros(na + nf)
        H_gamma, f[:na] = self._objective_model(E, objective, Gamma)
        H[:na, :na] += H_gamma
        g = body.gravity(q)
        Jc = body.contact_jacobian(q, mode)
        A, bu, bl = self._static_rows(E, k, 0)
        x = self._solve_qp(H, f, [(np.hstack([body.S_a.T, Jc.T]), g, g, True), (A, bu, bl, False)])
        return None if x is None else (x[:na], x[na:])

    def _qp(self, q, E, mode, objective, Gamma, F, targets, delta):
        """One Gauss-Newton QP over ``(dq, Gamma, F)`` at ``q`` (``E`` its effort matrix), linearised."""
        body = self.body
        model, data = body.model, body.data
        nv, na, k = body.nv, len(JOINTS), len(mode_feet(mode))
        nf = 6 * k
        angles = body.joint_angles(q)
        n = nv + na + nf
        H = 1e-9 * np.eye(n)
        f = np.zeros(n)
        H[:nv, :nv] = 1e-6 * np.eye(nv)
        H_gamma, f[nv : nv + na] = self._objective_model(E, objective, Gamma)
        H[nv : nv + na, nv : nv + na] += H_gamma
        g = body.gravity(q)
        Jc = body.contact_jacobian(q, mode)
        D = pin.computeStaticTorqueDerivatives(model, data, q, sole_forces(body, mode, F))
        e = self._contact_error(q, targets)
        A_static, bu_static, bl_static = self._static_rows(E, k, nv)
        blocks = [(np.hstack([-D, body.S_a.T, Jc.T]), g, g, True),  # equilibrium, linearised in q
                  (np.hstack([Jc, np.zeros((nf, na + nf))]), -e, -e, True),  # contacts held
                  (A_static, bu_static, bl_static, False)]
        # joint limits and the trust region: simple bounds on dq
        upper, lower = np.full(nv, delta), np.full(nv, -delta)
        upper[body.v_index] = np.minimum(self.limits_q[:, 1] - angles, delta)
        lower[body.v_index] = np.maximum(self.limits_q[:, 0] - angles, -delta)
        if mode != "double":
            free = next(s for s in SIDES if s != mode)
            pin.computeJointJacobians(model, data, q)
            pin.framesForwardKinematics(model, data, q)
            row = np.zeros((1, n))
            row[0, :nv] = pin.getFrameJacobian(model, data, body.sole_frame[free], pin.LOCAL_WORLD_ALIGNED)[2]
            z = data.oMf[body.sole_frame[free]].translation[2]
            blocks.append((row, np.array([INFINITE]), np.array([SWING_CLEARANCE_M - z]), False))
        x = self._solve_qp(H, f, blocks, (upper, lower))
        return None if x is None else x[:nv]

    def optimum_at(self, q, mode, objective, Gamma, F, rounds: int = 8, rtol: float = 1e-9):
        """The exact (convex) best ``(Gamma, F)`` at fixed ``q`` by Newton QPs; None if nothing is feasible.

        Stops when a round lowers the objective by less than ``rtol`` (relative)."""
        E = self._effort_matrix(q)
        value = None
        for _ in range(rounds):
            out = self._inner_qp(q, E, mode, objective, Gamma)
            if out is None:
                return None if value is None else (value, Gamma, F)
            G_new, F_new = out
            new = objective.value(E @ G_new)
            if value is not None and new >= value * (1 - rtol):
                break  # converged (the model is convex; no decrease means we are at its optimum)
            Gamma, F, value = G_new, F_new, new
        return value, Gamma, F

    # ----------------------------------------------------------------- solve
    def solve(self, q0: np.ndarray, mode: str, objective, delta: float = 0.1, max_iter: int = 50,
              tol: float = 1e-4, like_for_like: bool = False) -> FastIKResult:
        """The configuration of least ``objective`` reachable from ``q0`` with the contacts of ``mode`` held.

        ``like_for_like``: solve Jorgensen et al.'s descent's own problem instead -- Eq. 23's torques, only
        the contacts and the joint limits held (:mod:`humanoid_pb.ik.like_for_like`); the result's torques,
        wrenches and potential are then Eq. 23's."""
        start = time.perf_counter()
        self.failures = []
        body = self.body
        if self.actuator_limits is None:
            self.actuator_limits = effort_limits(body.params)
        targets = {
            s: p for s, p in body.sole_poses(q0).items() if s in {FOOT_SIDE[f] for f in mode_feet(mode)}
        }
        if like_for_like:
            q, history, iterations = gauss_newton(self, q0.copy(), mode, objective, targets)
            Gamma, F = min_norm_balance(body, q, mode)[:2]
            return FastIKResult(mode, q, history[-1], Gamma, F.reshape(-1, 6), iterations,
                                time.perf_counter() - start, history, contact_drift(body, q0, q, mode),
                                self.solver, tuple(self.failures))
        q = q0.copy()
        # the Newton model's first point: the least-norm balance of gravity (not Eq. 23's Gamma(q), which
        # costs a mass-matrix inverse and two pseudo-inverses); one round from it is a balanced upper bound
        balance = np.linalg.lstsq(np.hstack([body.S_a.T, body.contact_jacobian(q, mode).T]), body.gravity(q),
                                  rcond=None)[0]
        na = len(JOINTS)
        found = self.optimum_at(q, mode, objective, balance[:na], balance[na:], rounds=1)
        if found is None:
            raise ValueError("no balanced torques within the contact "
                             f"constraints at the start in mode {mode!r} "
                             f"({self.failures[-1]})")
        f, Gamma, F = found
        history = [f]
        iterations = 0
        for iterations in range(1, max_iter + 1):
            dq = self._qp(q, self._effort_matrix(q), mode, objective, Gamma, F, targets, delta)
            if dq is None:
                delta /= 2
                if delta < 1e-4:
                    break
                continue
            q_new = self._project_contacts(pin.integrate(body.model, q, dq), mode, targets)
            # one Newton round: a balanced (Gamma, F) inside the cones, so its potential is a true upper bound
            found = self.optimum_at(q_new, mode, objective, Gamma, F, rounds=1)
            if found is not None and found[0] < f:
                improvement = (f - found[0]) / f
                q, (f, Gamma, F) = q_new, found
                history.append(f)
                delta = min(delta * 1.5, MAX_STEP_RAD)
                if improvement < tol:
                    break
            else:
                delta /= 2
                if delta < 1e-4:
                    break
        # the exact optimum at the final configuration
        polished = self.optimum_at(q, mode, objective, Gamma, F)
        if polished is not None and polished[0] < f:
            f, Gamma, F = polished
            history.append(f)
        return FastIKResult(mode, q, f, Gamma, F.reshape(-1, 6), iterations, time.perf_counter() - start,
                            history, contact_drift(body, q0, q, mode), self.solver, tuple(self.failures))
