"""A long run's inputs averaged over blocks of samples: a fit simulates a fraction of the steps.

The model is a linear ODE whose right-hand side is a sum of the terms' rises and gains
(:mod:`.terms`).  Over a block of ``D`` seconds, short against every time constant, the
winding responds to the block's mean right-hand side: the interval's exact solution
weighs each sample's forcing by ``exp(-lam (t_end - t))``, which differs from the mean
weight by at most ``lam D``.  So a simulation on the blocks' grid, each block's rises and
gains averaged over its samples (weighted by their intervals), misses the full rate's
only by a share ``lam D`` of the fluctuations within a block, where keeping one sample
per block misses by all of them (``python benchmarks/block_means.py``: the plant's 10 Hz
random profile with speed losses, blocks of 15 samples, RC = 80.5 s: 0.0007 K rms and
0.007 K at most from the full rate's free run, against 0.25 K rms and 2.9 K for kept
samples).

What is averaged is each term's contribution, computed from the full-rate signals: a
term that combines arrays of the log linearly (:meth:`~.terms.Term.forms`: ``effort**2``,
``|velocity|``) has them averaged once, so each simulation costs the blocks, not the samples.
A channel read outside a contribution (a slow mass's airflow) is the block's first
sample: the mass's time constant, longer than the winding's, smooths what that misses.
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields
from functools import cached_property

import numpy as np

from .signals import Signals


@dataclass(frozen=True)
class BlockSignals(Signals):
    """Signals on a grid of block starts (``starts``, sample indices of ``full``), each term's contribution
    the block's mean (module docstring).  Build with :func:`blocked`."""

    full: Signals | None = field(default=None, repr=False)
    starts: np.ndarray | None = field(default=None, repr=False)
    _forms: dict = field(default_factory=dict, repr=False, compare=False)

    def contribution(self, term, params) -> tuple[np.ndarray | float, np.ndarray | float]:
        if term.name not in self._forms:
            forms = term.forms(self.full)
            self._forms[term.name] = None if forms is None else tuple(None if f is None else self.mean(f)
                                                                       for f in forms)
        forms = self._forms[term.name]
        if forms is not None:
            return term.combine(params, forms)
        rise, gain = term.contribution(params, self.full)
        return self.mean(rise), self.mean(gain)

    def map_arrays(self, fn):
        raise TypeError("a block-averaged run is not sliced or mapped: "
                        "do it to the full-rate signals and block them "
                        "again (block_means.blocked)")

    def mean(self, values):
        """Each block's mean of ``values`` (one per sample of ``full``), weighted by the samples' intervals; a
        number stays a number.  The last grid point's block has no interval after it: its own sample."""
        if np.ndim(values) == 0:
            return values
        values = np.asarray(values, dtype=float)
        inner, weights, spans = self._grid
        sums = np.add.reduceat(values[:-1] if weights is None else values[:-1] * weights, inner)
        out = np.empty(self.starts.size)
        with np.errstate(invalid="ignore", divide="ignore"):  # a block of equal timestamps: its first sample
            out[:inner.size] = np.where(spans > 0.0, sums / spans, values[inner])
        out[inner.size:] = values[-1]
        return out

    @cached_property
    def _grid(self) -> tuple[np.ndarray, np.ndarray | None, np.ndarray]:
        """The starts with an interval after them, the intervals (``None``: uniform, as counts), each block's
        span."""
        full = self.full
        inner = self.starts[self.starts < full.n - 1]
        if full.uniform_dt_s is not None:
            return inner, None, np.diff(np.append(inner, full.n - 1)).astype(float)
        return inner, full.dt_s, np.diff(np.append(full.time_s[inner], full.time_s[-1]))


def blocked(signals: Signals, starts: np.ndarray) -> BlockSignals:
    """``signals`` averaged over the blocks that begin at ``starts`` (increasing sample indices, the first
    0)."""
    starts = np.asarray(starts, dtype=np.intp)
    if starts.size == 0 or starts[0] != 0 or np.any(np.diff(starts) <= 0) or starts[-1] >= signals.n:
        raise ValueError(f"block starts must increase from sample 0 within the {signals.n} samples")
    kept = signals.map_arrays(lambda x: x[starts])
    return BlockSignals(**{f.name: getattr(kept, f.name) for f in fields(Signals)}, full=signals,
                        starts=starts)
