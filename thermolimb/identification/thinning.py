"""Fewer rows for long logs: fits compare every ``k``-th sample of a series.

A log at 10 Hz for days holds millions of samples, while a thermal response
changes over minutes.  The fits keep their signals at the full rate (the
simulation, the filters) but compare at every ``k``-th sample, ``k`` the
smallest stride that leaves at most ``MAX_FIT_SAMPLES``: a thermal residual is
smooth over many samples, so the sum of squares hardly changes, while the
matrices the solvers keep (rows x parameters) and their factorisations shrink
``k`` times.  The standard errors stay consistent, as they allow for serial
correlation: fewer rows, each less correlated with the next.
"""

from __future__ import annotations

import numpy as np

MAX_FIT_SAMPLES = 100_000  # rows compared per fit


def fit_stride(series) -> int:
    """The stride at which a fit compares ``series`` (each with ``fit_samples``, the samples it is fitted on)."""
    return max(1, -(-sum(s.fit_samples for s in series) // MAX_FIT_SAMPLES))


def fit_rows(series, stride: int) -> np.ndarray:
    """The samples of one series a fit compares: every ``stride``-th of those it is fitted on (its ``fit_mask``:
    a scheme holding blocks of the run out; all of them without one)."""
    rows = np.arange(series.n) if series.fit_mask is None else np.flatnonzero(series.fit_mask)
    return rows[::stride]


def thinned(values: np.ndarray, series, stride: int) -> np.ndarray:
    """Every ``stride``-th sample of each series in ``values`` (the samples each is fitted on, the series'
    concatenated): what the fit compares, in its order."""
    if stride == 1:
        return np.asarray(values)
    bounds = np.cumsum([s.fit_samples for s in series])[:-1]
    return np.concatenate([part[::stride] for part in np.split(np.asarray(values), bounds)])


def coarse(series, stride: int):
    """``series`` at every ``stride``-th sample, each sample's inputs held until the next kept one.

    A screen that only ranks starting points simulates this, ``stride`` times fewer steps: the ranking needs the
    basins, not the last digit.  A kept sample, not the block's mean: heat goes with the square of the effort, and
    a mean loses the block's variance, so it heats less on every block, where a kept sample is right on average
    (on the 1 h, 1 Hz random holds of ``tests/test_identification.py``, blocks of 5 samples miss the full rate's
    free run by up to 1.85 K of its 33 K rise with means, 0.98 K with kept samples).  A fit whose values are kept
    runs on the full rate."""
    return series if stride <= 1 else series.slice(0, series.n, stride)
