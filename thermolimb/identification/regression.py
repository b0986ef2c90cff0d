"""The regression form of the model (Jorgensen et al., Eq. 7) built from logs, and its identifiability check.

Rearranging the model ``RC dT/dt + T = T_offset + sum_k X_k theta_k`` gives one
linear equation per sample in the unknowns ``[RC, theta..., T_offset]``:

    T_i = [-dT/dt_i, X_i, 1] . [RC, theta, T_offset]

Temperature is low-pass filtered and differentiated (Jorgensen et al.'s low-pass
derivative).  With ``consistent=True`` every regressor goes through the *same*
zero-phase filter as the temperature, so the filtered signals satisfy the same
linear ODE exactly and the filter introduces no bias; ``consistent=False``
reproduces Jorgensen et al., who filtered effort at 1 Hz and temperature at 0.015 Hz.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Sequence

import numpy as np

from ..logs import ActuatorSeries
from ..model.block_means import blocked
from ..model.guard import instance
from ..model.model import model_parameters
from ..model.signals import Signals
from ..model.terms import Parameter
from ..util.errors import IdentifiabilityError
from .thinning import fit_stride


@dataclass(frozen=True)
class Regression:
    """Stacked regression ``y ~ X theta`` with ``theta`` in the model's parameter order."""

    X: np.ndarray
    y: np.ndarray
    parameters: tuple[Parameter, ...]
    effort: np.ndarray  # the (unfiltered) efforts of the rows, to describe poor excitation

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(p.name for p in self.parameters)


def _uniform(series: ActuatorSeries) -> ActuatorSeries:
    """Resample onto a uniform grid at the median interval when sampling jitters by more than 1 %."""
    dt = np.diff(series.time_s)
    step = float(np.median(dt))
    if np.max(np.abs(dt - step)) <= 0.01 * step:
        return series
    t = np.arange(series.time_s[0], series.time_s[-1] + 0.5 * step, step)
    t = t[t <= series.time_s[-1]]
    s = series.signals

    def at(x):
        if x is None:
            return None
        if x.ndim == 1:
            return np.interp(t, s.time_s, x)
        return np.column_stack([np.interp(t, s.time_s, c) for c in x.T])

    sig = replace(s.map_arrays(at), time_s=t)
    return ActuatorSeries(series.actuator, sig, at(series.temperature_C))


def lowpass(x: np.ndarray, cutoff_hz: float | None, dt_s: float, axis: int = 0) -> np.ndarray:
    """Zero-phase second-order Butterworth low-pass; no filtering when the cutoff is None or above Nyquist.

    ``scipy.signal``'s ``sosfiltfilt`` of ``butter(2, cutoff_hz / nyquist, output="sos")``, to rounding: the
    same odd extension of 9 samples at each end, the filter started at rest at the first value, run forward
    and then backward.  Each pass is the one section's difference equation, solved as a banded
    unit-lower-triangular system by LAPACK (``dtbtrs``); importing ``scipy.signal`` cost every command line
    half a second."""
    nyquist = 0.5 / dt_s
    x = np.asarray(x, dtype=float)
    if cutoff_hz is None or cutoff_hz >= nyquist:
        return x
    b, a = butterworth2(cutoff_hz / nyquist)
    moved = np.moveaxis(x, axis, 0)
    n, edge = moved.shape[0], PAD_SAMPLES
    if n <= edge:
        raise ValueError(f"a low-pass filter needs more than {edge} samples, got {n}")
    extended = np.concatenate(
        [2.0 * moved[:1] - moved[edge:0:-1], moved, 2.0 * moved[-1:] - moved[-2 : -edge - 2 : -1]]
    )
    flat = extended.reshape(extended.shape[0], -1)
    forward = _section(b, a, flat)
    both = _section(b, a, forward[::-1])[::-1]
    return np.moveaxis(both[edge:-edge].reshape(moved.shape), 0, axis)


PAD_SAMPLES = 9  # sosfiltfilt's odd extension for one second-order section: 3 * (2 * 1 + 1) samples


def butterworth2(wn: float) -> tuple[tuple[float, float, float], tuple[float, float]]:
    """The second-order digital Butterworth low-pass at ``wn`` (the cutoff over Nyquist, in (0, 1)), by the
    bilinear transform with the cutoff prewarped: numerator ``(b0, b1, b2)`` and denominator ``(a1, a2)``
    (``a0 = 1``)."""
    k = np.tan(0.5 * np.pi * wn)
    norm = 1.0 / (1.0 + np.sqrt(2.0) * k + k * k)
    b0 = k * k * norm
    return (b0, 2.0 * b0, b0), (2.0 * (k * k - 1.0) * norm, (1.0 - np.sqrt(2.0) * k + k * k) * norm)


def _section(b: tuple[float, float, float], a: tuple[float, float], u: np.ndarray) -> np.ndarray:
    """``y[n] + a1 y[n-1] + a2 y[n-2] = b0 u[n] + b1 u[n-1] + b2 u[n-2]`` down the columns of ``u``, from the
    state the filter holds after the column's first value for ever (its input and output before it held at
    ``u[0]`` and at ``u[0]`` times the gain at rest)."""
    from scipy.linalg.lapack import dtbtrs

    u0 = u[0]
    rest = u0 * (sum(b) / (1.0 + a[0] + a[1]))
    before = np.concatenate([np.broadcast_to(u0, (2,) + u0.shape), u])  # u[-2], u[-1] at rest
    rhs = b[0] * before[2:] + b[1] * before[1:-1] + b[2] * before[:-2]
    rhs[0] -= (a[0] + a[1]) * rest
    rhs[1] -= a[1] * rest
    bands = np.empty((3, u.shape[0]))
    # the unit diagonal and the two below it (LAPACK's band storage)
    bands[0], bands[1], bands[2] = 1.0, a[0], a[1]
    y, info = dtbtrs(bands, rhs, uplo="L", diag="U")
    if info != 0:
        raise ValueError(f"the low-pass filter's solve failed (LAPACK info {info})")
    return y


def lowpass_derivative(x: np.ndarray, cutoff_hz: float | None, dt_s: float) -> tuple[np.ndarray, np.ndarray]:
    """Filtered signal and its time derivative (central differences of the filtered signal)."""
    xf = lowpass(x, cutoff_hz, dt_s)
    return xf, np.gradient(xf, dt_s)


def term_features(terms: Sequence[str], s: Signals, temperature_C: np.ndarray) -> np.ndarray:
    """The regressors of every term, side by side, in parameter order."""
    blocks = []
    for name in terms:
        f = instance(name).features(s, temperature_C)
        if f is None:
            raise IdentifiabilityError(
                f"term '{name}' is not linear in its parameters; identify it by output error"
            )
        blocks.append(f)
    return np.hstack(blocks) if blocks else np.zeros((s.n, 0))


# a long log is block-averaged before filtering: blocks of at most 1/20 of the cutoff's period
BLOCKS_PER_PERIOD = 20


def build_regression(
    series: Sequence[ActuatorSeries],
    terms: tuple[str, ...],
    cutoff_hz: float | None,
    consistent: bool = True,
    effort_cutoff_hz: float | None = 1.0,
    subtract_ambient_C: float | None = None,
) -> Regression:
    """Stack the regression rows of several series of one actuator.

    ``subtract_ambient_C``: Jorgensen et al.'s form ``y = T - T_amb`` (use the
    log's ambient column when it has one, else this constant); ``None`` keeps
    ``y = T`` with the ambient inside ``T_offset``.  A long log's rows are
    thinned (:mod:`~thermolimb.identification.thinning`): each signal is
    averaged over blocks of :func:`block_samples` (the consistent filtering
    only), filtered, one column at a time, and only the kept rows of it are
    held (the 6 M-row Parquet's knee: 1.9 s at the full rate).
    """
    Xs, ys, efforts = [], [], []
    stride = fit_stride(series)
    for raw in series:
        ser = _uniform(raw)
        dt = float(ser.time_s[1] - ser.time_s[0])
        m = block_samples(cutoff_hz, dt, stride) if consistent else 1
        coarse = (lambda x: x) if m == 1 else blocked(ser.signals, np.arange(0, ser.n, m)).mean
        n, dt_c = -(-ser.n // m), m * dt
        trim = 0 if cutoff_hz is None else min(int(np.ceil(0.5 / (cutoff_hz * dt_c))), n // 10)
        keep = np.arange(trim, n - trim, max(1, stride // m))
        centre = keep * m + m // 2  # the sample at the middle of each kept block
        if raw.fit_mask is not None:  # the samples fitted on (on a resampled grid, the nearest sample's)
            inside = raw.fit_mask[np.clip(np.searchsorted(raw.time_s, ser.time_s[centre]), 0, raw.n - 1)]
            keep, centre = keep[inside], centre[inside]
        T = lowpass(coarse(ser.temperature_C), cutoff_hz, dt_c)
        rows = -gradient_at(T, keep, dt_c)
        if consistent:
            feats = _kept_features(terms, ser.signals, ser.temperature_C, keep,
                                   lambda x: lowpass(coarse(x), cutoff_hz, dt_c))
        else:
            s = ser.signals
            smooth = replace(s, **{name: lowpass(getattr(s, name), effort_cutoff_hz, dt)
                                   for name in ("effort", "velocity", "current_A", "power_W")
                                   if getattr(s, name) is not None})
            feats = _kept_features(terms, smooth, T, keep, lambda x: x)
        y = T[keep]
        del T
        if subtract_ambient_C is not None:
            amb = ser.signals.ambient_C
            y -= lowpass(coarse(amb), cutoff_hz, dt_c)[keep] if amb is not None else subtract_ambient_C
        Xs.append(np.column_stack([rows, feats, np.ones(rows.size)]))
        ys.append(y)
        efforts.append(ser.signals.effort[centre])
    params = model_parameters(terms)
    X = Xs[0] if len(Xs) == 1 else np.vstack(Xs)
    reg = Regression(X, np.concatenate(ys), params, np.concatenate(efforts))
    check_identifiable(reg, series[0].actuator)
    return reg


def block_samples(cutoff_hz: float | None, dt_s: float, stride: int) -> int:
    """Samples averaged into one before filtering a long log: at most the rows' stride, and a block at most
    :data:`BLOCKS_PER_PERIOD` times shorter than the filter's period (a block mean passes what the filter
    keeps: its gain at the cutoff is ``sinc(1/BLOCKS_PER_PERIOD)``, 0.996).  1: filter at the full rate."""
    if cutoff_hz is None or stride <= 1:
        return 1
    return int(max(1, min(stride, np.floor(1.0 / (BLOCKS_PER_PERIOD * cutoff_hz * dt_s)))))


def gradient_at(x: np.ndarray, at: np.ndarray, dt_s: float) -> np.ndarray:
    """``np.gradient(x, dt_s)[at]`` without the whole-length array: central differences inside, one-sided at
    the ends."""
    lo = np.clip(at - 1, 0, x.size - 1)
    hi = np.clip(at + 1, 0, x.size - 1)
    return (x[hi] - x[lo]) / ((hi - lo) * dt_s)


def _kept_features(terms, s: Signals, temperature_C: np.ndarray, keep: np.ndarray, smooth) -> np.ndarray:
    """The regressors of every term (:func:`term_features`) at the rows ``keep``, each column passed through
    ``smooth`` at the full rate first, one term and one column at a time."""
    columns = []
    for name in terms:
        block = term_features((name,), s, temperature_C)
        columns += [smooth(block[:, j])[keep] for j in range(block.shape[1])]
        del block
    return np.column_stack(columns) if columns else np.zeros((keep.size, 0))


def mean_ambient_C(series: Sequence[ActuatorSeries], default_C: float) -> float:
    """Mean logged ambient over the series, or ``default_C`` when a series has no ambient column."""
    amb = [s.signals.ambient_C for s in series]
    if all(a is not None for a in amb):
        return float(np.mean(np.concatenate(amb)))
    return float(default_C)


# A regressor whose part independent of the others is below this fraction of
# its own variation cannot be told apart from them.
IDENTIFIABLE_FRACTION = 1e-3


def independent_fractions(X: np.ndarray) -> np.ndarray:
    """For each column, the fraction of its variation not explained by the other columns.

    From the column-scaled Gram matrix ``G``: the residual of column ``j``
    regressed on the others has squared norm ``G_jj - g_j' pinv(G_-j) g_j``
    (exact, and well defined when the *other* columns are collinear among
    themselves).  Columns other than the intercept (all ones) are measured
    against their centred norm.
    """
    norms = np.linalg.norm(X, axis=0)
    safe = np.where(norms > 0, norms, 1.0)
    G = (X.T @ X) / np.outer(safe, safe)
    p = G.shape[0]
    residual = np.empty(p)
    for j in range(p):
        others = [k for k in range(p) if k != j]
        g = G[others, j]
        residual[j] = np.sqrt(
            max(G[j, j] - g @ np.linalg.pinv(G[np.ix_(others, others)], rcond=1e-12) @ g, 0.0)
        )
    return _relative(X, norms, safe, residual)


def collinear_partners(X: np.ndarray, j: int) -> list[int]:
    """Columns that carry most of column ``j``'s explained part (scaled regression weights > 0.2 of the
    largest)."""
    norms = np.linalg.norm(X, axis=0)
    safe = np.where(norms > 0, norms, 1.0)
    G = (X.T @ X) / np.outer(safe, safe)
    others = [k for k in range(G.shape[0]) if k != j]
    weights = np.abs(np.linalg.pinv(G[np.ix_(others, others)], rcond=1e-12) @ G[others, j])
    if not weights.size or weights.max() == 0:
        return []
    return [others[i] for i in np.flatnonzero(weights > 0.2 * weights.max())]


def _relative(X, norms, safe, residual):
    means = X.mean(axis=0)
    centred = np.sqrt(np.maximum(norms**2 - X.shape[0] * means**2, 0.0)) / safe
    is_intercept = np.all(X == 1.0, axis=0)
    spread = np.where(is_intercept, 1.0, centred)
    with np.errstate(divide="ignore", invalid="ignore"):
        fraction = np.where((norms > 0) & (spread > 0), residual / spread, 0.0)
    return np.nan_to_num(fraction)


def check_identifiable(reg: Regression, actuator: str) -> None:
    """Raise :class:`IdentifiabilityError` for the first parameter the rows cannot determine."""
    fractions = independent_fractions(reg.X)
    for j, p in enumerate(reg.parameters):
        if fractions[j] < IDENTIFIABLE_FRACTION:
            col = reg.X[:, j]
            levels = np.unique(np.round(reg.effort, 3)).size
            partners = tuple(reg.parameters[k].name for k in collinear_partners(reg.X, j))
            what = "constant" if np.ptp(col) == 0 else (
                "almost a combination of the regressors of "
                f"{', '.join(partners)} ({fractions[j]:.1e} independent)")
            raise IdentifiabilityError(
                f"cannot identify {p.name} ({p.description}) for "
                f"actuator {actuator}: its regressor is {what} "
                f"in the training data, where effort takes {levels} distinct level(s) "
                f"between {reg.effort.min():.3g} and {reg.effort.max():.3g}; a log needs {p.excitation}",
                parameter=p.name, partners=partners,
            )
