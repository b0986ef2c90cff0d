"""The exact discrete map of a linear network whose inputs are held over an interval (zero-order hold)."""

from __future__ import annotations

import numpy as np
from scipy.linalg import expm


def zero_order_hold(A: np.ndarray, B: np.ndarray, dt_s: float) -> tuple[np.ndarray, np.ndarray]:
    """``(Phi, Gamma)`` with ``x(t + dt) = Phi x(t) + Gamma u`` for ``dx/dt = A x + B u`` and ``u`` held.

    One matrix exponential of the block matrix ``[[A, B], [0, 0]] dt``: exact
    for any interval, so a network stays stable at any control rate.  Every
    linear network of the suite (the plant, the winding observer, the
    offline observer of a log) is stepped through this one function.
    """
    A = np.atleast_2d(np.asarray(A, float))
    B = np.asarray(B, float).reshape(A.shape[0], -1)
    n, m = B.shape
    M = np.zeros((n + m, n + m))
    M[:n, :n], M[:n, n:] = A, B
    E = expm(M * dt_s)
    return E[:n, :n].copy(), E[:n, n:].copy()
