"""Error measures between measured and simulated temperatures."""

from __future__ import annotations

import numpy as np


def fit_percent(measured: np.ndarray, predicted: np.ndarray) -> float:
    """100 (1 - ||y - y_hat|| / ||y - mean(y)||): 100 is perfect, 0 is no better than the mean."""
    return fit_metrics(measured, predicted)["fit_percent"]


def fit_metrics(measured: np.ndarray, predicted: np.ndarray) -> dict[str, float]:
    """``{"rmse_K", "max_abs_K", "fit_percent"}`` of a simulation against measurements."""
    return pieces_metrics([(measured, predicted)])


def pieces_metrics(pieces) -> dict[str, float]:
    """:func:`fit_metrics` of pieces ``(measured, predicted)`` taken together, without joining them (one
    temporary of a piece's length at a time)."""
    pieces = [(np.asarray(m, float), np.asarray(p, float)) for m, p in pieces]
    n = sum(m.size for m, _ in pieces)
    squared = largest = spread = 0.0
    mean = sum(float(np.sum(m)) for m, _ in pieces) / n if n else float("nan")
    for measured, predicted in pieces:
        err = np.subtract(predicted, measured)
        squared += float(np.dot(err, err))
        largest = max(largest, float(np.max(np.abs(err, out=err)))) if err.size else largest
        np.subtract(measured, mean, out=err)
        spread += float(np.dot(err, err))
    rmse = float(np.sqrt(squared / n)) if n else float("nan")
    fit = float(100.0 * (1.0 - np.sqrt(squared / spread))) if spread > 0 else float("nan")
    return {"rmse_K": rmse, "max_abs_K": largest if n else float("nan"), "fit_percent": fit}


def ar1_variance_factor(residuals: np.ndarray) -> float:
    """Variance inflation for serially correlated residuals, (1 + rho) / (1 - rho) with rho the lag-1
    autocorrelation.

    Least-squares standard errors assume independent residuals; thermal
    residuals are smooth, so their effective sample count is smaller.
    """
    r = np.asarray(residuals) - np.mean(residuals)
    denom = float(np.dot(r, r))
    if denom == 0 or r.size < 3:
        return 1.0
    rho = float(np.clip(np.dot(r[1:], r[:-1]) / denom, 0.0, 0.999))
    return (1.0 + rho) / (1.0 - rho)


def correlation_length(residuals: np.ndarray, threshold: float = 0.05) -> int:
    """The first lag (samples) at which the residual's autocorrelation falls below ``threshold`` (FFT, O(n log
    n))."""
    from scipy import fft

    r = np.asarray(residuals, float) - np.mean(residuals)
    n = r.size
    spectrum = fft.rfft(r, fft.next_fast_len(2 * n, real=True))
    power = np.square(spectrum.real)
    power += np.square(spectrum.imag)
    del spectrum
    acf = fft.irfft(power)[:n]
    if acf[0] <= 0:
        return 1
    below = np.flatnonzero(acf < threshold * acf[0])
    return int(below[0]) if below.size else n


def hac_covariance(X: np.ndarray, residuals: np.ndarray) -> np.ndarray:
    """Parameter covariance of a linear least-squares fit whose residuals are serially correlated
    (Newey-West).

    ``(X'X)^-1 S (X'X)^-1`` with ``S`` the Bartlett-weighted sum of the
    score's autocovariances up to ``L`` lags, ``L`` the larger of Newey and
    West's rule ``4 (n/100)^(2/9)`` and twice the residual's
    :func:`correlation_length` (at most ``n/4``).  The regressions of the
    method of Jorgensen et al. are low-pass filtered, so their residuals stay correlated
    over many samples: an AR(1) inflation there (``(1+rho)/(1-rho)`` with
    ``rho`` near 1) overstated the standard errors 12-15 times against their
    spread over noise draws (``tests/test_identification.py``).

    The weighted sum is ``G'G + H'G + G'H`` with ``G`` the scores and
    ``H[t] = sum_k w_k G[t+k]`` (``k = 1..L``) one correlation of each score
    with the Bartlett weights (by FFT, ``scipy.fft``): exact, in O(n log n) time and
    O(n p) memory whatever ``L``, where a sum over lags costs O(n p^2 L).
    """
    from scipy import fft

    X = np.asarray(X, float)
    r = np.asarray(residuals, float)
    n = r.size
    lags = int(min(max(4.0 * (n / 100.0) ** (2.0 / 9.0), 2 * correlation_length(r)), n // 4))
    scores = X * r[:, None]
    S = scores.T @ scores
    if lags >= 1:
        weights = np.concatenate([[0.0], 1.0 - np.arange(1, lags + 1) / (lags + 1.0)])
        size = fft.next_fast_len(n + lags, real=True)
        kernel = np.conj(fft.rfft(weights, size))  # a correlation: H[t] = sum_k w_k G[t+k], none past the end
        cross = np.empty_like(S)
        for i, score in enumerate(scores.T):
            cross[i] = fft.irfft(fft.rfft(score, size) * kernel, size)[:n] @ scores
        S += cross + cross.T
    inverse = np.linalg.inv(X.T @ X)
    return inverse @ S @ inverse


def chi2_sf(x: float, df: int) -> float:
    """The chi-squared distribution's survival function at ``x`` on ``df`` degrees of freedom
    (``scipy.stats.chi2``'s own special function: importing ``scipy.stats`` cost a command line 0.3 s)."""
    from scipy.special import chdtrc

    return float(chdtrc(df, x))


def chi2_isf(level: float, df: int) -> float:
    """The value the chi-squared distribution on ``df`` degrees of freedom passes with probability ``level``
    (``scipy.stats.chi2.ppf(1 - level, df)``, in its own form)."""
    from scipy.special import gammaincinv

    return float(2.0 * gammaincinv(0.5 * df, 1.0 - level))


def information_criteria(residual: np.ndarray, n_params: int) -> dict[str, float]:
    """Gaussian ``{"aic", "bic"}`` of a fit: ``n ln(RSS/n) + 2k`` and ``n ln(RSS/n) + k ln n``.

    Serially correlated residuals make both overstate evidence; compare them
    between models on the same data, alongside held-out error.
    """
    n = residual.size
    fit_term = n * np.log(np.mean(np.asarray(residual) ** 2))
    return {"aic": float(fit_term + 2 * n_params), "bic": float(fit_term + n_params * np.log(n))}


def scaled_inverse(matrix: np.ndarray) -> np.ndarray:
    """The pseudo-inverse of a symmetric positive semi-definite matrix taken on its unit-diagonal form:
    parameters whose units differ by many decades (an effort logged in mA makes a heat gain 10^6 times
    smaller) keep their covariance, where a plain ``pinv`` cuts the small directions and the standard errors
    collapse."""
    diagonal = np.sqrt(np.clip(np.diag(matrix), 0.0, None))
    d = np.where(diagonal > 0, 1.0 / np.where(diagonal > 0, diagonal, 1.0), 0.0)
    return np.linalg.pinv(matrix * np.outer(d, d)) * np.outer(d, d)
