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
    """The stride at which a fit compares ``series`` (a sequence of objects with ``n`` samples)."""
    return max(1, -(-sum(s.n for s in series) // MAX_FIT_SAMPLES))


def thinned(values: np.ndarray, series, stride: int) -> np.ndarray:
    """Every ``stride``-th sample of each series in ``values``, the series' samples concatenated."""
    if stride == 1:
        return np.asarray(values)
    bounds = np.cumsum([s.n for s in series])[:-1]
    return np.concatenate([part[::stride] for part in np.split(np.asarray(values), bounds)])

