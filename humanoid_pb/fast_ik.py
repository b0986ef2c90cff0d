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
Unlike the seed's method, ``Gamma`` is any torque that balances the robot
within its contact constraints, not only the dynamically consistent one.
"""

from __future__ import annotations

import time
from ctypes import c_int

import daqp
import numpy as np
import pinocchio as pin

from .actuators import effort_limits, effort_matrix
from .constants import FOOT_SIDE, JOINTS, SIDES, leg_joint, mode_feet
from .descent import DescentResult, contact_drift
from .statics import WholeBody

MU = 0.6  # friction pyramid
MU_YAW_M = 0.05  # yaw friction moment per newton of normal force
MIN_NORMAL_N = 20.0
COP_MARGIN_M = 0.015
SWING_CLEARANCE_M = 0.05
_EQ = 5  # daqp: active and immutable
_INF = 1e30


class FastThermalIK:
    """Reusable solver for one robot (caches the model's constant data)."""

    def __init__(self, body: WholeBody):
        self.body = body
        p = body.params
        self.limits_q = np.array([body.params.limits(j) for j in JOINTS])
        for side in SIDES:  # the IK's working range: knees never straight (singular, and torque-free in a rigid model)
            k = JOINTS.index(leg_joint(side, "knee"))
            self.limits_q[k, 0] = max(self.limits_q[k, 0], p.knee_min_rad)
        self.half_sole = np.array(p.sole_m) / 2.0 - COP_MARGIN_M
        self.actuator_limits = None

    # ----------------------------------------------------------- linear algebra
    def _wrench_rows(self, k: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Rows over one sole wrench ``(fx, fy, fz, mx, my, mz)`` with bl <= R w <= bu."""
        lx, ly = self.half_sole
        rows = [
            [0, 0, 1, 0, 0, 0],  # fz >= f_min
            [1, 0, -MU, 0, 0, 0], [-1, 0, -MU, 0, 0, 0],  # |fx| <= mu fz
            [0, 1, -MU, 0, 0, 0], [0, -1, -MU, 0, 0, 0],  # |fy| <= mu fz
            [0, 0, -ly, 1, 0, 0], [0, 0, -ly, -1, 0, 0],  # |mx| <= (w/2) fz: centre of pressure across the sole
            [0, 0, -lx, 0, 1, 0], [0, 0, -lx, 0, -1, 0],  # |my| <= (l/2) fz: and along it
            [0, 0, -MU_YAW_M, 0, 0, 1], [0, 0, -MU_YAW_M, 0, 0, -1],
        ]
        R = np.array(rows, float)
        bu = np.r_[_INF, np.zeros(len(rows) - 1)]
        bl = np.r_[MIN_NORMAL_N, np.full(len(rows) - 1, -_INF)]
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
            Jc = self.body.contact_jacobian(q, mode)
            q = pin.integrate(self.body.model, q, -np.linalg.pinv(Jc) @ e)
        return q

    def _external_forces(self, q: np.ndarray, mode: str, F: np.ndarray):
        model = self.body.model
        fext = [pin.Force.Zero() for _ in range(model.njoints)]
        for i, foot in enumerate(mode_feet(mode)):
            frame = model.frames[self.body.sole_frame[FOOT_SIDE[foot]]]
            fext[frame.parentJoint] += frame.placement.act(pin.Force(F[6 * i : 6 * i + 6]))
        return fext

    # -------------------------------------------------------------------- QPs
    def _qp(self, q, mode, objective, Gamma, F, targets, delta, move: bool):
        """One Gauss-Newton QP; ``move=False`` fixes the configuration (the exact inner problem)."""
        body = self.body
        model, data = body.model, body.data
        nv, na, k = body.nv, len(JOINTS), len(mode_feet(mode))
        nf = 6 * k
        angles = body.joint_angles(q)
        E = effort_matrix(body.rods, angles)
        efforts = E @ Gamma
        # Newton model of the objective in the efforts (its Hessian is diagonal and >= 0), in Gamma
        scale = 1.0 / max(objective.value(efforts), 1e-12)
        grad = scale * objective.gradient(efforts)
        hess = scale * objective.hessian_diag(efforts)
        n = nv + na + nf
        H = np.zeros((n, n))
        f = np.zeros(n)
        reg = 1e-9
        H[:nv, :nv] = (1e-6 if move else 1.0) * np.eye(nv)
        H_gamma = E.T @ (hess[:, None] * E)
        H[nv : nv + na, nv : nv + na] = H_gamma + reg * np.eye(na)
        f[nv : nv + na] = E.T @ grad - H_gamma @ Gamma
        H[nv + na :, nv + na :] = reg * np.eye(nf)
        g = body.gravity(q)
        Jc = body.contact_jacobian(q, mode)
        D = pin.computeStaticTorqueDerivatives(model, data, q, self._external_forces(q, mode, F)) if move else np.zeros((nv, nv))
        rows, bu, bl, sense = [], [], [], []

        def add(A, upper, lower, equality=False):
            rows.append(A)
            bu.append(upper)
            bl.append(lower)
            sense.append(np.full(len(upper), _EQ if equality else 0, dtype=c_int))

        add(np.hstack([-D, body.S_a.T, Jc.T]), g, g, equality=True)  # equilibrium
        if move:
            e = self._contact_error(q, targets)
            add(np.hstack([Jc, np.zeros((nf, na + nf))]), -e, -e, equality=True)
        W, wbu, wbl = self._wrench_rows(k)
        add(np.hstack([np.zeros((len(W), nv + na)), W]), wbu, wbl)
        lim = self.actuator_limits
        add(np.hstack([np.zeros((na, nv)), E, np.zeros((na, nf))]), lim, -lim)
        # joint limits and the trust region, as rows over dq
        A_dq = np.zeros((na, n))
        A_dq[np.arange(na), body.v_index] = 1.0
        hi = self.limits_q[:, 1] - angles
        lo = self.limits_q[:, 0] - angles
        if move:
            add(A_dq, np.minimum(hi, delta), np.maximum(lo, -delta))
            A_base = np.zeros((6, n))
            A_base[:, :6] = np.eye(6)
            add(A_base, np.full(6, delta), np.full(6, -delta))
            if mode != "double":
                free = next(s for s in SIDES if s != mode)
                pin.computeJointJacobians(model, data, q)
                pin.framesForwardKinematics(model, data, q)
                Jz = pin.getFrameJacobian(model, data, body.sole_frame[free], pin.LOCAL_WORLD_ALIGNED)[2]
                z = data.oMf[body.sole_frame[free]].translation[2]
                row = np.zeros((1, n))
                row[0, :nv] = Jz
                add(row, np.array([_INF]), np.array([SWING_CLEARANCE_M - z]))
        else:
            A_fix = np.zeros((nv, n))
            A_fix[:, :nv] = np.eye(nv)
            add(A_fix, np.zeros(nv), np.zeros(nv), equality=True)
        A = np.vstack(rows)
        x, _, flag, _ = daqp.solve(H, f, A, np.concatenate(bu), np.concatenate(bl), np.concatenate(sense))
        if flag < 1:
            return None
        return x[:nv], x[nv : nv + na], x[nv + na :]

    def optimum_at(self, q, mode, objective, Gamma, F, rounds: int = 8):
        """The exact (convex) best ``(Gamma, F)`` at fixed ``q`` by Newton QPs; None if nothing is feasible."""
        E = effort_matrix(self.body.rods, self.body.joint_angles(q))
        value = None
        for _ in range(rounds):
            out = self._qp(q, mode, objective, Gamma, F, None, 0.0, move=False)
            if out is None:
                return None if value is None else (value, Gamma, F)
            _, G_new, F_new = out
            new = objective.value(E @ G_new)
            if value is not None and new >= value * (1 - 1e-10):
                break  # converged (the model is convex; a non-decrease means we are at its optimum)
            Gamma, F, value = G_new, F_new, new
        return value, Gamma, F

    # ----------------------------------------------------------------- solve
    def solve(self, q0: np.ndarray, mode: str, objective, delta: float = 0.1, max_iter: int = 50,
              tol: float = 1e-7) -> DescentResult:
        start = time.perf_counter()
        body = self.body
        if self.actuator_limits is None:
            self.actuator_limits = effort_limits(body.params)
        targets = {s: p for s, p in body.sole_poses(q0).items() if s in {FOOT_SIDE[f] for f in mode_feet(mode)}}
        statics = body.statics(q0, mode)
        q = q0.copy()
        found = self.optimum_at(q, mode, objective, statics.torques_Nm, statics.contact_wrenches.ravel())
        if found is None:
            raise ValueError(f"no balanced torques within the contact constraints at the start in mode {mode!r}")
        f, Gamma, F = found
        history = [f]
        iterations = 0
        for iterations in range(1, max_iter + 1):
            out = self._qp(q, mode, objective, Gamma, F, targets, delta, move=True)
            if out is None:
                delta /= 2
                if delta < 1e-4:
                    break
                continue
            dq, _, _ = out
            q_new = self._project_contacts(pin.integrate(body.model, q, dq), mode, targets)
            found = self.optimum_at(q_new, mode, objective, Gamma, F)
            if found is not None and found[0] < f:
                improvement = (f - found[0]) / f
                q, (f, Gamma, F) = q_new, found
                history.append(f)
                delta = min(delta * 1.5, 0.3)
                if improvement < tol:
                    break
            else:
                delta /= 2
                if delta < 1e-4:
                    break
        return DescentResult("fast", mode, q, f, iterations, time.perf_counter() - start, history,
                             contact_drift(body, q0, q, mode), torques_Nm=Gamma, contact_wrenches=F.reshape(-1, 6))
