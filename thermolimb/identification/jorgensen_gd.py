"""Jorgensen et al.'s identification, kept to reproduce it: z-scored batch gradient descent (Eqs. 7-16)."""

from __future__ import annotations

import numpy as np

from ..model.terms import DEFAULT_MODEL
from .base import ThermalEstimator
from .metrics import ar1_variance_factor
from .regression import build_regression, mean_ambient_C


class JorgensenGradientDescent(ThermalEstimator):
    """Batch gradient descent on ``y = T - T_amb = [RC, theta, P_bias R] . [-dT/dt, X, 1]``.

    As in Jorgensen et al.: temperature low-passed at 0.015 Hz and differentiated,
    effort low-passed at 1 Hz before forming the regressors, every regressor
    but the bias z-scored (Eq. 12), ``y`` z-scored, all parameters start at
    zero, plain gradient steps with a fixed learning rate (Eq. 11), then
    unscaling by Eqs. 15-16.

    Parameters
    ----------
    learning_rate
        ``alpha`` of Eq. 11 on the z-scored problem.
    max_iter
        Iteration limit.
    tol
        Stop when an iteration lowers the loss by less than ``tol`` times the loss.
    target_loss
        Stop as soon as the loss (Eq. 9, in the *unscaled* units of ``y``, K^2/2)
        is at most this value; used to run it "to the same loss" as another method.
    ambient_C
        Ambient temperature when the log has no ``ambient`` column (Jorgensen et al. measured 25 degC).
    """

    method = "jorgensen_gd"
    constrained = False  # Jorgensen et al.'s method: unconstrained, as Eq. 7 is

    def __init__(self, model=DEFAULT_MODEL, temperature_cutoff_hz: float = 0.015,
                 effort_cutoff_hz: float = 1.0, learning_rate: float = 0.2, max_iter: int = 200_000,
                 tol: float = 1e-13, target_loss: float | None = None, ambient_C: float = 25.0):
        super().__init__(model)
        self.temperature_cutoff_hz = temperature_cutoff_hz
        self.effort_cutoff_hz = effort_cutoff_hz
        self.learning_rate = learning_rate
        self.max_iter = max_iter
        self.tol = tol
        self.target_loss = target_loss
        self.ambient_C = ambient_C

    def _fit(self, series, terms):
        reg = build_regression(series, terms, self.temperature_cutoff_hz, consistent=False,
                               effort_cutoff_hz=self.effort_cutoff_hz, subtract_ambient_C=self.ambient_C)
        coef, self.loss_, self.n_iter_ = zscore_gradient_descent(
            reg.X, reg.y, self.learning_rate, self.max_iter, self.tol, self.target_loss)
        residual = reg.X @ coef - reg.y
        scale = np.linalg.norm(reg.X, axis=0)
        scale[scale == 0] = 1.0
        Xs = reg.X / scale
        sigma2 = float(residual @ residual) / max(reg.y.size - Xs.shape[1], 1) * ar1_variance_factor(residual)
        cov = sigma2 * np.linalg.pinv(Xs.T @ Xs) / np.outer(scale, scale)
        values = coef.copy()
        values[-1] += mean_ambient_C(series, self.ambient_C)  # T_offset = T_amb + P_bias R
        return values, cov


def zscore_gradient_descent(X: np.ndarray, y: np.ndarray, learning_rate: float, max_iter: int,
                            tol: float, target_loss: float | None) -> tuple[np.ndarray, float, int]:
    """Eqs. 9-16: batch gradient descent on z-scored regressors (the last column of ``X`` is the bias).

    Returns the unscaled coefficients, the final loss (Eq. 9, unscaled) and
    the number of iterations.
    """
    F = X[:, :-1]
    x_mean, x_std = F.mean(axis=0), F.std(axis=0)
    x_std[x_std == 0] = 1.0
    y_mean, y_std = y.mean(), y.std() or 1.0
    Z = np.column_stack([(F - x_mean) / x_std, np.ones(y.size)])  # Eq. 12; the bias is not scaled
    zy = (y - y_mean) / y_std
    m = y.size
    theta = np.zeros(Z.shape[1])  # zero initial guess
    target = None if target_loss is None else target_loss / y_std**2  # L_z = L / sigma_y^2
    previous = np.inf
    loss = np.inf
    iteration = 0
    for iteration in range(1, max_iter + 1):
        residual = Z @ theta - zy
        loss = 0.5 * float(residual @ residual) / m  # Eq. 9
        if target is not None and loss <= target:
            break
        if previous - loss < tol * loss:
            break
        previous = loss
        theta -= learning_rate * (Z.T @ residual) / m  # Eqs. 10-11
    slopes = y_std / x_std * theta[:-1]  # Eq. 16
    bias = y_mean - slopes @ x_mean + y_std * theta[-1]  # Eq. 15 (P_bias R)
    return np.append(slopes, bias), loss * y_std**2, iteration
