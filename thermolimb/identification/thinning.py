"""Fewer rows and fewer steps for long logs: fits compare every ``k``-th sample and simulate blocks of ``k``.

A log at 10 Hz for days holds millions of samples, while a thermal response
changes over minutes.  The fits compare at every ``k``-th sample, ``k`` the
smallest stride that leaves at most ``MAX_FIT_SAMPLES``: a thermal residual is
smooth over many samples, so the sum of squares hardly changes, while the
matrices the solvers keep (rows x parameters) and their factorisations shrink
``k`` times.  The standard errors stay consistent, as they allow for serial
correlation: fewer rows, each less correlated with the next.

Output error also simulates such a log on blocks of ``k`` samples, each term's
contribution averaged over its block (:mod:`~thermolimb.model.block_means`), while
the model's time constants are long against a block
(``BLOCK_TIME_CONSTANTS``); a fit that ends where they are not is fitted again at
the full rate.  Validation, residuals and every check after the fit run at the
full rate."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..model.block_means import blocked
from ..model.terms import TERMS

MAX_FIT_SAMPLES = 100_000  # rows compared per fit
# a fit simulates a long log on blocks of its stride while each time constant spans at least this many blocks
# (python benchmarks/block_means.py, blocks of 1.5 s: the free run misses the full rate's by 0.0007 K rms at
# 54 blocks, 0.004 K at 20, 0.014 K at 10; that log's sensor floor is 0.06 K)
BLOCK_TIME_CONSTANTS = 40.0


def fit_stride(series, most: int | None = None) -> int:
    """The stride at which a fit compares ``series`` (each with ``fit_samples``, the samples it is fitted on):
    the smallest that leaves at most ``most`` of them (default :data:`MAX_FIT_SAMPLES`)."""
    return max(1, -(-sum(s.fit_samples for s in series) // (most or MAX_FIT_SAMPLES)))


def fit_rows(series, stride: int) -> np.ndarray:
    """The samples of one series a fit compares: every ``stride``-th of those it is fitted on (its
    ``fit_mask``: a scheme holding blocks of the run out; all of them without one)."""
    rows = np.arange(series.n) if series.fit_mask is None else np.flatnonzero(series.fit_mask)
    return rows[::stride]


def thinned(values: np.ndarray, series, stride: int) -> np.ndarray:
    """Every ``stride``-th sample of each series in ``values`` (the samples each is fitted on, the series'
    concatenated): what the fit compares, in its order."""
    if stride == 1:
        return np.asarray(values)
    bounds = np.cumsum([s.fit_samples for s in series])[:-1]
    return np.concatenate([part[::stride] for part in np.split(np.asarray(values), bounds)])


def on_blocks(series, rows: np.ndarray, stride: int):
    """``series`` averaged over blocks of ``stride`` samples (:mod:`~thermolimb.model.block_means`), the
    blocks' starts including ``rows``; and the places of ``rows`` among them.  A fit simulates this,
    ``stride`` times fewer steps, and compares it where the full rate would be compared."""
    grid = np.arange(0, series.n, stride)
    starts = grid if np.array_equal(grid, rows) else np.union1d(grid, rows)
    shown = replace(series, signals=blocked(series.signals, starts),
                    temperature_C=series.temperature_C[starts], fit_mask=None)
    return shown, np.searchsorted(starts, rows)


def longest_block(model, series) -> int:
    """The most samples of ``series`` one block may hold for ``model`` by :func:`blocks_allowed`'s rule (each
    time constant at least :data:`BLOCK_TIME_CONSTANTS` blocks long): a stride beyond it is simulated at the
    full rate."""
    steps = [(_fastest_s(model, s), float(np.diff(s.time_s).max(initial=0.0))) for s in series]
    return max(1, min((int(fastest / (BLOCK_TIME_CONSTANTS * step)) for fastest, step in steps if step > 0),
                      default=1))


def blocks_allowed(model, shown) -> bool:
    """Whether the model's time constants on the blocked series ``shown`` are each at least
    ``BLOCK_TIME_CONSTANTS`` blocks long."""
    return all(_fastest_s(model, s) >= BLOCK_TIME_CONSTANTS * float(np.diff(s.time_s).max(initial=0.0))
               for s in shown)


def _fastest_s(model, series) -> float:
    """``model``'s shortest time constant on ``series``: the winding's where it is fastest (a gain such as
    cooling by motion shortens it), each slow mass's."""
    slow = [model.params[p.name] for t in model.terms if TERMS[t].carries_state for p in TERMS[t].parameters
            if p.unit == "s"]
    return min([1.0 / float(np.max(model.forcing(series.signals)[1])), *slow])
