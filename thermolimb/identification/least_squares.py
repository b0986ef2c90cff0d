"""Direct least squares on Jorgensen et al.'s regression (Eq. 7)."""

from __future__ import annotations

import numpy as np

from ..model.terms import DEFAULT_MODEL
from .base import ThermalEstimator
from .metrics import hac_covariance
from .regression import build_regression, mean_ambient_C


def solve_least_squares(X: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, float, np.ndarray]:
    """Minimise ``|X theta - y|^2``: returns ``(theta, loss, covariance)``, ``loss = mean(r^2) / 2`` (Eq. 9).

    Normal equations on unit-norm columns (a p x p solve after one pass over
    the rows), which is accurate here because the regressors are few and the
    check for identifiability has already refused near-collinear ones.
    The covariance allows for serially correlated residuals (Newey-West,
    :func:`~thermolimb.identification.metrics.hac_covariance`).
    """
    scale = np.linalg.norm(X, axis=0)
    scale[scale == 0] = 1.0
    Xs = X / scale
    gram = Xs.T @ Xs
    coef = np.linalg.solve(gram, Xs.T @ y)
    residual = y - Xs @ coef
    loss = 0.5 * float(np.mean(residual**2))
    cov = hac_covariance(Xs, residual) * y.size / max(y.size - coef.size, 1) / np.outer(scale, scale)
    return coef / scale, loss, cov


class LeastSquares(ThermalEstimator):
    """Solve the regression of Eq. 7 in one step (``numpy.linalg.lstsq`` on scaled columns).

    Parameters
    ----------
    model
        Comma-separated terms or a sequence of them; every term must be linear
        in its parameters.
    cutoff_hz
        Low-pass cutoff (zero phase) of the temperature; ``None`` for none.
        Jorgensen et al.'s 0.015 Hz by default.
    filtering
        ``"consistent"``: every regressor goes through the temperature's filter,
        which keeps the filtered equation exact.  ``"jorgensen"``: Jorgensen et al.'s rows
        exactly (effort filtered at ``effort_cutoff_hz`` before squaring,
        ``y = T - T_amb``), to compare with :class:`JorgensenGradientDescent` on the
        same problem.
    ambient_C
        With ``filtering="jorgensen"``, the ambient when the log has no ``ambient`` column.
    """

    method = "least_squares"
    constrained = False  # Jorgensen et al.'s method: unconstrained, as Eq. 7 is

    def __init__(self, model=DEFAULT_MODEL, cutoff_hz: float | None = 0.015,
                 filtering: str = "consistent", effort_cutoff_hz: float = 1.0, ambient_C: float = 25.0):
        super().__init__(model)
        self.cutoff_hz = cutoff_hz
        self.filtering = filtering
        self.effort_cutoff_hz = effort_cutoff_hz
        self.ambient_C = ambient_C

    def _fit(self, series, terms):
        if self.filtering not in ("consistent", "jorgensen"):
            raise ValueError(f"filtering must be 'consistent' or 'jorgensen', got {self.filtering!r}")
        as_published = self.filtering == "jorgensen"
        reg = build_regression(series, terms, self.cutoff_hz, consistent=not as_published,
                               effort_cutoff_hz=self.effort_cutoff_hz,
                               subtract_ambient_C=self.ambient_C if as_published else None)
        values, self.loss_, cov = solve_least_squares(reg.X, reg.y)
        if as_published:
            values[-1] += mean_ambient_C(series, self.ambient_C)
        return values, cov
