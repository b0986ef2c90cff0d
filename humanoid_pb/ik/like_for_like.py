"""The fast thermal IK on Jorgensen et al.'s own objective: Eq. 23's torques, differentiated analytically.

Eq. 23's torque is the *minimum-norm* balancing torque.  ``Gamma(q) =
Xbar' N_c' g`` lies in the range of ``X = S_a N_c``, that is in ``S_a
null(J_c)``; every torque that only changes the internal forces
(``S_a' dGamma`` in the range of ``J_c'``) is orthogonal to it.  So among all
``(Gamma, F)`` with ``S_a' Gamma + J_c' F = g`` it is the one of least
``|Gamma|`` (tested equal to Eq. 23's to 1e-8 N m), and it needs no mass
matrix.  Its optimality conditions

    Gamma - S_a lam = 0,    J_c lam = 0,    S_a' Gamma + J_c' F = g

form a square, nonsingular linear system ``K z = r`` in ``z = (Gamma, F,
lam)``.  Differentiating it gives ``dGamma/dq`` from Pinocchio's analytic
derivatives (of the static torques under the wrenches ``F``, and of the
soles' velocities under ``lam``), so a Gauss-Newton step on the descent's
objective ``f(q) = phi(E(q) Gamma(q))`` over the contacts' null space costs
one small factorisation, where Jorgensen et al.'s descent (Eq. 30) spends ``|V| + 1``
whole-body statics on a finite-difference gradient.

:func:`gauss_newton` runs those steps (the fast method's like-for-like mode,
``FastThermalIK.solve(..., like_for_like=True)``); each is kept only if the
exact ``f`` at the new configuration (contacts re-projected) is lower.  It
solves the descent's problem, with the descent's freedom: Eq. 23's wrenches
are not held inside the friction cones and soles, the efforts not within
their limits, and the knees may straighten past the IK's working range (the
descent does, to 0.08 rad, on some temperature profiles); only the contacts
and the robot's joint limits hold.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
from scipy.linalg import lu_factor, lu_solve

from ..constants import FOOT_SIDE, JOINTS, mode_feet
from ..model.actuation import ROD_BLOCKS, effort_matrix

FD_STEP_RAD = 1e-6  # finite difference of the rods' 2 x 2 effort blocks only (six joint angles)
MAX_STEP_RAD = 0.4  # trust region cap; on 20 random profiles 0.1 took 2.19 ms median, 0.2 2.02, 0.4 1.99


def min_norm_balance(body, q: np.ndarray, mode: str):
    """``(Gamma, F, lam, lu)`` at ``q``: Eq. 23's torques (JOINTS order), the sole wrenches (flat, sole
    frames), the multiplier and the factorised system (for :func:`torque_jacobian`)."""
    na, nv = len(JOINTS), body.nv
    Jc = body.contact_jacobian(q, mode)
    nf = Jc.shape[0]
    K = np.zeros((na + nf + nv, na + nf + nv))
    K[:na, :na] = np.eye(na)
    K[:na, na + nf :] = -body.S_a
    K[na : na + nf, na + nf :] = Jc
    K[na + nf :, :na] = body.S_a.T
    K[na + nf :, na : na + nf] = Jc.T
    lu = lu_factor(K)
    z = lu_solve(lu, np.r_[np.zeros(na + nf), body.gravity(q)])
    return z[:na], z[na : na + nf], z[na + nf :], lu


def sole_forces(body, mode: str, F: np.ndarray) -> list:
    """Pinocchio's external forces (one per joint, in its frame) of the sole wrenches ``F`` (flat, sole
    frames)."""
    model = body.model
    fext = [pin.Force.Zero() for _ in range(model.njoints)]
    for i, foot in enumerate(mode_feet(mode)):
        frame = model.frames[body.sole_frame[FOOT_SIDE[foot]]]
        fext[frame.parentJoint] += frame.placement.act(pin.Force(F[6 * i : 6 * i + 6]))
    return fext


def torque_jacobian(body, q: np.ndarray, mode: str, F: np.ndarray, lam: np.ndarray, lu) -> np.ndarray:
    """``dGamma/dq`` (JOINTS x nv, tangent space) of the minimum-norm balance, by implicit differentiation."""
    model, data = body.model, body.data
    na, nv, nf = len(JOINTS), body.nv, len(F)
    R = np.zeros((na + nf + nv, nv))
    pin.computeForwardKinematicsDerivatives(model, data, q, lam, np.zeros(nv))
    for i, foot in enumerate(mode_feet(mode)):
        dv_dq, _ = pin.getFrameVelocityDerivatives(model, data, body.sole_frame[FOOT_SIDE[foot]], pin.LOCAL)
        R[na + 6 * i : na + 6 * i + 6] = dv_dq
    # d(J_c'F - g)/dq
    R[na + nf :] = -pin.computeStaticTorqueDerivatives(model, data, q, sole_forces(body, mode, F))
    return -lu_solve(lu, R)[:na]


def efforts_and_jacobian(body, q: np.ndarray, mode: str) -> tuple[np.ndarray, np.ndarray]:
    """The actuator efforts under Eq. 23 at ``q`` and their derivative (ACTUATORS x nv)."""
    Gamma, F, lam, lu = min_norm_balance(body, q, mode)
    angles = body.joint_angles(q)
    E = effort_matrix(body.rods, angles)
    efforts = E @ Gamma
    J = E @ torque_jacobian(body, q, mode, F, lam, lu)
    for pair, (rows, cols) in ROD_BLOCKS.items():  # the rod forces' change with the rods' geometry
        rod, (pitch, roll), tau = body.rods[pair], angles[cols], Gamma[cols]
        for k, shifted in enumerate(((pitch + FD_STEP_RAD, roll), (pitch, roll + FD_STEP_RAD))):
            moved = np.linalg.solve(rod.length_jacobian(*shifted).T, tau)
            J[rows, body.v_index[cols[k]]] += (moved - efforts[rows]) / FD_STEP_RAD
    return efforts, J


def gauss_newton(solver, q: np.ndarray, mode: str, objective, targets: dict, max_iter: int = 15,
                 tol: float = 1e-3) -> tuple[np.ndarray, list[float], int]:
    """Gauss-Newton on the descent's objective from ``q``: each step a QP over ``dq`` with the contacts held
    to first order, a trust region and the robot's joint limits as simple bounds, kept if the exact objective
    at the re-projected configuration is lower; stops when a kept step gains less than ``tol`` (relative).
    Returns ``(q, the objective after each kept step, iterations)``."""
    body = solver.body
    nv = body.nv
    limits = solver.robot_limits_q  # the robot's, as the descent has: no working range
    efforts, J = efforts_and_jacobian(body, q, mode)
    history = [objective.value(efforts)]
    delta, iterations = MAX_STEP_RAD, 0
    for iterations in range(1, max_iter + 1):
        f, gradient, hessian = objective.newton(efforts)
        scale = 1.0 / max(f, 1e-12)
        H = J.T @ ((scale * hessian)[:, None] * J)
        H += 1e-9 * max(np.trace(H) / nv, 1e-12) * np.eye(nv)
        Jc = body.contact_jacobian(q, mode)
        angles = body.joint_angles(q)
        upper, lower = np.full(nv, delta), np.full(nv, -delta)
        upper[body.v_index] = np.clip(limits[:, 1] - angles, 0.0, delta)
        lower[body.v_index] = np.clip(limits[:, 0] - angles, -delta, 0.0)
        zero = np.zeros(len(Jc))
        dq = solver._solve_qp(H, J.T @ (scale * gradient), [(Jc, zero, zero, True)], (upper, lower))
        if dq is None:
            break
        q_new = solver._project_contacts(pin.integrate(body.model, q, dq), mode, targets)
        efforts_new, J_new = efforts_and_jacobian(body, q_new, mode)
        f_new = objective.value(efforts_new)
        if f_new < f:
            q, efforts, J = q_new, efforts_new, J_new
            history.append(f_new)
            delta = min(delta * 1.5, MAX_STEP_RAD)
            if (f - f_new) / f < tol:
                break
        else:
            delta /= 4
            if delta < 1e-6:
                break
    return q, history, iterations
