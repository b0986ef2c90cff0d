"""Vectorised solution of the first-order recursion ``x[k+1] = a[k] x[k] + b[k]``.

Every free-run simulation of the effort-based model reduces to this recursion
(exact zero-order-hold discretisation of a scalar linear, possibly time-varying,
ODE).  A Python loop over a million samples costs about a second; this scan costs
a few milliseconds.

Method: with ``P[k] = prod_{j<k} a[j]`` the solution is

    x[k] = P[k] * (x[0] + sum_{j<k} b[j] / P[j+1])

which is a cumulative product and a cumulative sum.  To keep ``1 / P`` inside
floating-point range the series is cut into chunks whose total decay
(``-log P``) is at most ``MAX_DECAY_PER_CHUNK`` e-folds, carrying the state across
chunk boundaries.  A caller that has ``log a`` (``-rate * dt``) passes it: the
logarithm costs more than the rest of the scan (7355 samples: 53 us of ~240).

When ``a`` is one constant to rounding (a uniformly sampled log and a
time-invariant rate; see ``CONSTANT_A``), the chunks all share one decay, ``a^1 .. a^m``, worked out once and
kept, and short chunks run side by side (``_constant_factor``).  This is a first-order IIR filter:
``scipy.signal.lfilter`` ran it in one compiled pass, up to twice as fast on a long log, but importing
``scipy.signal`` cost every command line half a second.

When the series decays so fast that it would need many chunks for its length (a
time constant of a few samples), an associative scan is used instead: the pairs
``(a, b)`` compose as ``(a2, b2) o (a1, b1) = (a2 a1, a2 b1 + b2)``, so
``log2(n)`` vectorised passes give every prefix (Hillis-Steele).  It only
multiplies factors <= 1, so it cannot overflow.
"""

from __future__ import annotations

import numpy as np

MAX_DECAY_PER_CHUNK = 30.0  # e-folds: exp(30) ~ 1e13 keeps ~3 significant digits of headroom
_MIN_LOG_A = -MAX_DECAY_PER_CHUNK  # one step may decay at most this much (a >= 9e-14)
_MIN_A = float(np.exp(_MIN_LOG_A))
# Factors that differ by less than this share of their distance from 1 are one constant: a time grid of
# k * 0.1 s has steps that differ by rounding; taking their mean changes x by at most about 1e-9 of its size.
CONSTANT_A = 1e-9
# The associative scan costs about log2(n) passes over the n values; the chunked loop, one pass and about 15
# us of calls per chunk: it is the faster while its chunks number at most n log2(n) / ELEMENTS_PER_CHUNK
# (measured: 2 M samples, 1333 chunks: 70 ms looped against 300 ms associative; 4400 samples, 49 chunks: 0.66
# against 0.17 ms)
ELEMENTS_PER_CHUNK = 2000.0
# one constant factor's chunks run in a loop when they are at least this long, else side by side (measured, 15
# calls' best: 2 M samples in 67 chunks 9.5 ms looped against 21 ms side by side; 200,000 in 68, 1.1 against
# 1.5 ms; 20,000 in 71, 0.34 against 0.17 ms; in 834, 3.0 against 0.19 ms; lfilter, for scale, 10, 1.0, 0.10
# and 0.11 ms)
LOOPED_STEPS = 1000
# a recursion this short runs as a plain loop (a monitor's piece of a sample or two): no call overhead
SHORT = 8


def first_order_scan(a: np.ndarray, b: np.ndarray, x0: float, log_a: np.ndarray | None = None) -> np.ndarray:
    """Return ``x`` of length ``len(b) + 1`` with ``x[0] = x0`` and ``x[k+1] = a[k] x[k] + b[k]``.

    ``a`` must lie in ``[0, 1]`` (a stable, decaying recursion); values below
    ``exp(-30)`` are treated as ``exp(-30)``, which changes ``x`` by less than
    one part in 1e13.  A single number ``a`` is the same factor at every step.
    ``log_a``, when the caller has it, is ``log(a)`` (it saves computing it).
    """
    b = np.asarray(b, dtype=float)
    a = np.asarray(a, dtype=float)
    if b.shape[0] <= SHORT and np.all((a >= 0.0) & (a <= 1.0)) and (a.ndim == 0 or a.shape == b.shape):
        return _loop(a, b, x0)
    if a.ndim and b.shape != a.shape:
        raise ValueError(f"a and b must have the same shape, got {a.shape} and {b.shape}")
    return Recursion(a, log_a).run(b, x0)


class Recursion:
    """The factors ``a`` of ``x[k+1] = a[k] x[k] + b[k]`` made ready once for any number of ``b``: the chunks
    and their cumulative products (module docstring), the one constant factor, or (``chunks`` ``None``) the
    associative scan's choice.  A simulation's passes and a fit's evaluations at the same rate share them
    (:meth:`~thermolimb.model.signals.Signals.recursion`); :attr:`a` is the factors (a number when
    constant)."""

    def __init__(self, a: np.ndarray | float, log_a: np.ndarray | None = None):
        a = np.asarray(a, dtype=float)
        self.a, self.chunks, self._decay = a, None, None  # _decay: a constant factor's powers, once made
        if a.ndim == 0:
            if not 0.0 <= a <= 1.0:
                raise ValueError("first_order_scan needs 0 <= a <= 1 (a decaying recursion)")
            self.a = float(a)
            return
        n = a.shape[0]
        if n == 0:
            self.chunks = []
            return
        lowest, highest = a.min(), a.max()  # one pass each: the range check and the constant test share them
        if highest > 1.0 or lowest < 0.0:
            raise ValueError("first_order_scan needs 0 <= a <= 1 (a decaying recursion)")
        if highest - lowest <= CONSTANT_A * (1.0 - highest):
            self.a = float(np.mean(a))
            return
        if log_a is None:
            # a = 0 is a step that forgets: its log is clamped like any fast decay
            with np.errstate(divide="ignore"):
                log_a = np.log(a)
        log_a = np.maximum(log_a, _MIN_LOG_A)
        L = np.cumsum(log_a)  # log of the product of a up to step k: decreasing, -decay
        if -L[-1] / MAX_DECAY_PER_CHUNK > n * np.log2(max(n, 2)) / ELEMENTS_PER_CHUNK:
            return  # the associative scan
        a = np.maximum(a, _MIN_A)  # as the logarithm is clamped
        # decays: -L, for the chunks' ends, only when there is more than one
        self.chunks, start, decays = [], 0, None
        while start < n:
            offset = L[start - 1] if start > 0 else 0.0
            if L[-1] >= offset - MAX_DECAY_PER_CHUNK:
                stop = n
            else:  # the chunk ends where its decay passes MAX_DECAY_PER_CHUNK
                decays = -L if decays is None else decays
                stop = int(np.searchsorted(decays, MAX_DECAY_PER_CHUNK - offset, side="right"))
            stop = max(stop, start + 1)
            # decay[i] = prod_{j=start}^{start+i} a[j] = exp(L[start+i] - offset), in (exp(-30), 1]: a product
            # is half the cost of the exponential and as accurate (one rounding a step: ~1e-12 over 1e4 steps)
            self.chunks.append((start, stop, np.cumprod(a[start:stop])))
            start = stop

    @property
    def nbytes(self) -> int:
        """What it holds: its factors, and as many again in its chunks' products (a constant factor: its
        powers)."""
        if isinstance(self.a, float):
            return 8 + (0 if self._decay is None else self._decay.nbytes)
        return self.a.nbytes * (2 if self.chunks else 1)

    def run(self, b: np.ndarray, x0: float) -> np.ndarray:
        """``x`` for inputs ``b`` (one per factor) from ``x[0] = x0``."""
        b = np.asarray(b, dtype=float)
        if b.shape[0] <= SHORT:
            return _loop(np.asarray(self.a), b, x0)
        if isinstance(self.a, float):
            out, self._decay = _constant_factor(self.a, b, float(x0), self._decay)
            return out
        out = np.empty(b.shape[0] + 1)
        out[0] = x0
        if self.chunks is None:
            out[1:] = _associative_scan(self.a, b, float(x0))
            return out
        state = float(x0)
        for start, stop, decay in self.chunks:
            summed = np.cumsum(b[start:stop] / decay)
            summed += state
            np.multiply(decay, summed, out=out[start + 1 : stop + 1])
            state = out[stop]
        return out


def _loop(a: np.ndarray, b: np.ndarray, x0: float) -> np.ndarray:
    out = [float(x0)]
    for ak, bk in zip(np.broadcast_to(a, b.shape).tolist(), b.tolist()):
        out.append(ak * out[-1] + bk)
    return np.array(out)


def _constant_factor(a: float, b: np.ndarray, x0: float, decay: np.ndarray | None = None
                     ) -> tuple[np.ndarray, np.ndarray | None]:
    """The recursion with one factor ``a``: the chunked sums of the module docstring, every chunk ``m`` steps
    long (``MAX_DECAY_PER_CHUNK`` e-folds) with the same decay ``a^1 .. a^m``.  Long chunks run one after the
    other; shorter ones (``LOOPED_STEPS``) run side by side, as the columns of one array, and the states they
    hand on follow the recursion of factor ``a^m`` from chunk to chunk (the associative scan, over as many
    values as chunks). Returns the decay for the next call at the same factor (``decay``: one kept from an
    earlier call)."""
    n = b.shape[0]
    log_a = max(float(np.log(a)), _MIN_LOG_A) if a > 0.0 else _MIN_LOG_A
    m = n if log_a == 0.0 else max(1, min(n, int(MAX_DECAY_PER_CHUNK / -log_a)))
    if decay is None or decay.shape[0] != m:
        decay = np.cumprod(np.full(m, max(a, _MIN_A)))  # as a varying factor's chunks are
    chunks = -(-n // m)
    if m >= LOOPED_STEPS or chunks == 1:
        out = np.empty(n + 1)
        out[0] = state = x0
        for start in range(0, n, m):
            stop = min(start + m, n)
            d = decay[: stop - start]
            summed = np.cumsum(b[start:stop] / d)
            summed += state
            np.multiply(d, summed, out=out[start + 1 : stop + 1])
            state = out[stop]
        return out, decay
    out = np.zeros(chunks * m + 1)  # the last chunk filled out with inputs of 0
    out[0] = x0
    out[1 : n + 1] = b
    steps = out[1:].reshape(chunks, m).T / decay[:, None]  # column c: chunk c's steps
    np.cumsum(steps, axis=0, out=steps)
    steps *= decay[:, None]  # each chunk's solution from a zero state
    handed = np.empty(chunks)  # the state each chunk starts from
    handed[0] = x0
    handed[1:] = _associative_scan(np.full(chunks - 1, decay[-1]), steps[-1, :-1].copy(), float(x0))
    steps += decay[:, None] * handed
    out[1:].reshape(chunks, m)[...] = steps.T
    return out[: n + 1], decay


def _associative_scan(a: np.ndarray, b: np.ndarray, x0: float) -> np.ndarray:
    """``x[1:]`` of the recursion by prefix composition of ``(a, b)`` pairs, in log2(n) passes."""
    A = a.copy()
    B = b.copy()
    B[0] += a[0] * x0  # fold the initial state into the first step
    A[0] = 0.0
    shift = 1
    n = A.size
    while shift < n:
        # compose each element with the prefix ending `shift` places before it
        B[shift:] = A[shift:] * B[:-shift] + B[shift:]
        A[shift:] = A[shift:] * A[:-shift]
        shift *= 2
    return B
