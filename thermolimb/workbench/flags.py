"""Warnings about fitted values a user should not trust as physics.

A parameter pinned at a bound or vanishing (``betaR -> 0``: the log shows no
such heating), an offset far from any temperature the log supports, a time
constant the log is too short or too coarse to show.  Each flag is one
sentence; ``fit``, ``compare`` and ``diagnose`` print them, put them in their
JSON and on their plots.
"""

from __future__ import annotations

import contextlib
import re
import weakref
from typing import Mapping, Sequence

import numpy as np

from ..effects.effort_bias import both_signs
from ..identification.bounds import OFFSET_MARGIN_K
from ..logs import ActuatorSeries
from ..model.model import ThermalModel, redefines_offset
from ..model.parameter_units import spaced
from ..model.terms import LONG_TIME_CONSTANT
from ..util.numbers import plus_minus, significant
from .excitation import excitation
from .floor import FLOOR_FACTOR, sensor_floor

SHORT_TIME_CONSTANT = 0.5  # a time constant shorter than this many sampling intervals is not seen
TRADES = 0.95  # a value this correlated with another's estimate (in magnitude) trades with it
# the first-order model's time constant and heat coefficients, whose needs the excitation's counts measure
FIRST_ORDER = ("RC_s", "betaR_K_per_effort2", "beta_biasR_K_per_effort")
MAX_RELATIVE_STDERR = 0.5  # a value known to worse than half of itself is flagged


def parameter_flags(model: ThermalModel, stderr: Mapping[str, float], series: Sequence[ActuatorSeries],
                    held: Sequence[str] = (), train_rmse_K: float | None = None,
                    covariance: np.ndarray | None = None) -> list[str]:
    """One sentence per fitted value that looks like an artefact of the log rather than physics (values
    ``held``, not fitted, are the user's or the ambient's and are not judged).  A value the log does not pin
    down says why (:func:`uncertainty_cause`, from the training error ``train_rmse_K``; the parameter it
    trades with, from the fit's ``covariance`` over ``model.parameters``)."""
    flags = []
    cause = _Cause(series, train_rmse_K, model, covariance)
    units = series[0].units if series else {}
    duration = max(s.duration_s for s in series)
    dt = min(s.median_dt_s for s in series)
    for p in model.parameters:
        if p.name in held:
            continue
        v = model.params[p.name]
        scale = abs(p.typical) if p.typical else 1.0
        if p.unit == "s":
            if v >= LONG_TIME_CONSTANT * duration * (1.0 - 1e-6):
                flags.append(f"{p.name} = {significant(v, 3)} s is {LONG_TIME_CONSTANT:g}x the log or "
                             f"longer ({duration:.0f} s): the log shows the start of a change, not its "
                             f"time constant")
            elif v < SHORT_TIME_CONSTANT * dt:
                flags.append(f"{p.name} = {v:.3g} s is shorter than "
                             f"{SHORT_TIME_CONSTANT:g} sampling intervals "
                             f"({dt:.3g} s): the log cannot show it")
            else:
                flags += [flag for flag in (_uncertain(p, v, stderr.get(p.name), units, cause),) if flag]
            continue
        if p.lower == 0.0 and v <= 1e-6 * scale and not p.nuisance:
            flags.append(f"{p.name} vanishes ({v:.2g} {p.unit_in(units)}): "
                         "the log shows no effect of this term"
                         f"{cause.wanting(p)}")
            continue
        at_bound = False
        for bound in (p.lower, p.upper):
            if np.isfinite(bound) and bound != 0.0 and abs(v - bound) <= 1e-4 * max(abs(bound), scale):
                at_bound = True
                flags.append(f"{p.name} = {v:.3g} {p.unit_in(units)} is at "
                             f"its bound {bound:g}: the fit wants more than "
                             f"this term can give; another effect is missing")
        flag = None if at_bound else _uncertain(p, v, stderr.get(p.name), units, cause)
        if flag:
            flags.append(flag)
    if not redefines_offset(model.terms) and "T_offset_C" not in held:
        flag = _offset_flag(model.params["T_offset_C"], series)
        if flag:
            flags.append(flag)
    return flags


_UNREAD = [False]  # inside :func:`unread`: no flag's cause is worked out


@contextlib.contextmanager
def unread():
    """Flags that nobody reads (a stability replicate's fits: only their verdicts count), their causes not
    worked out: a large standard error's flag then ends "(its cause not worked out)".  What a flag starts with
    -- the value, and that it is flagged, all any judgement reads -- is unchanged.  On the 6 M-row Parquet's
    knee the causes' readings (its excitation and its sensor's floor, on each replicate's trimmed runs) took
    1.15 s of the ten replicates' 8.1 s."""
    before, _UNREAD[0] = _UNREAD[0], True
    try:
        yield
    finally:
        _UNREAD[0] = before


class _Cause:
    """Why standard errors are large, worked out once per fit and only when one is
    (:func:`uncertainty_cause`)."""

    def __init__(self, series, train_rmse_K, model=None, covariance=None):
        self.series, self.train_rmse_K, self._said = series, train_rmse_K, None
        self.model, self.covariance = model, covariance

    def __call__(self, p) -> str:
        if _UNREAD[0]:
            return "(its cause not worked out)"
        if self._said is None:
            self._said = uncertainty_cause(self.series, self.train_rmse_K)
        misfit, counts = self._said
        if misfit:
            return misfit
        partner = _partner(self.model, self.covariance, p.name)
        if partner is not None:
            return ("so the log does not pin it down: it trades with "
                    f"{partner[0]} (correlation {partner[1]:+.3f}), "
                    f"the log fixing a combination of the two rather than each")
        lacking = self._lacking(p)
        if lacking:
            return f"so the log does not pin it down: it lacks {', '.join(lacking)}"
        if lacking is not None and self._small(p):
            return ("too small an effect for this log to tell from "
                    "none, though the log holds what identifying "
                    f"it needs ({counts})")
        return (
            f"so the log does not pin it down (identifying it needs {p.excitation}; the log holds {counts})"
        )

    def wanting(self, p) -> str:
        """What identifying ``p`` needs, for a vanishing value's flag: for the first-order model's, what the
        log lacks of it, or nothing where it holds it all (the BLDC bench's Joule coefficient on twelve effort
        levels was told it needed three)."""
        lacking = None if _UNREAD[0] else self._lacking(p)
        if lacking is None:
            return f" (identifying it needs {p.excitation})"
        return (
            f"; it lacks {', '.join(lacking)}" if lacking else ", though it holds what identifying it needs"
        )

    def _lacking(self, p) -> list[str] | None:
        """What the log lacks of the counts the first-order model's values need (:data:`FIRST_ORDER`: the
        counts measure their needs), or ``None`` for any other value."""
        return _readings(self.series)[0].lacking() if p.name in FIRST_ORDER else None

    def _small(self, p) -> bool:
        """Whether a heat coefficient of the first-order model, on a log that holds what the counts say it
        needs (for the bias, efforts of both signs too), is a small value: its large relative error is then
        not the log's want (the README tour's bias after ``+ speed_losses``, 0.000477 +- 0.00035 K/(N m) on a
        log of 14 effort levels, was once said to need three).  A time constant is never "small"."""
        return p.unit != "s" and (p.name != "beta_biasR_K_per_effort" or both_signs(self.series)[0])


def _partner(model: ThermalModel | None, covariance, name: str) -> tuple[str, float] | None:
    """The fitted parameter whose estimate moves most with ``name``'s, and their correlation, where its
    magnitude is at least :data:`TRADES`; else ``None`` (a held value has no variance, so no partner)."""
    names = [p.name for p in model.parameters] if model is not None else []
    if covariance is None or np.shape(covariance) != (len(names), len(names)) or name not in names:
        return None
    sd = np.sqrt(np.clip(np.diag(covariance), 0.0, None))
    i = names.index(name)
    with np.errstate(divide="ignore", invalid="ignore"):
        corr = np.where((sd > 0) & (sd[i] > 0), covariance[i] / (sd * sd[i]), 0.0)
    corr[i] = 0.0
    j = int(np.argmax(np.abs(corr)))
    return (names[j], float(corr[j])) if abs(corr[j]) >= TRADES else None


def uncertainty_cause(series, train_rmse_K: float | None) -> tuple[str | None, str]:
    """``(sentence, counts)``: the sentence, when the log excites the model (:mod:`.excitation`) and the model
    still fits it far worse than the sensor's floor (:mod:`.floor`) -- then the model misses something, and
    the standard errors are large for that reason, not for lack of excitation; otherwise ``None``."""
    shown, floor = _readings(series)
    if train_rmse_K is None or not shown.ample:
        return None, shown.words()
    # the floor is the readings' own noise: an upper bound, so that a misfit is not overstated
    if floor.floor_K <= 0 or train_rmse_K <= FLOOR_FACTOR * floor.floor_K:
        return None, shown.words()
    return (f"large because the model misses something, not for lack of excitation: its training error, "
            f"{train_rmse_K:.3f} K, is {train_rmse_K / floor.floor_K:.0f} times the sensor's floor of "
            f"{floor.floor_K:.3f} K, while the log holds {shown.words()} -- run diagnose", shown.words())


_READINGS: dict = {}  # the last few logs' (excitation, floor), by their series' identities
READINGS_KEPT = 4


def _readings(series) -> tuple:
    """The excitation and the sensor floor of ``series``: a diagnosis flags every fit of one log (a stability
    replicate's dozen on the 6 M-row Parquet's knee took 0.25 s each), so the last :data:`READINGS_KEPT` logs'
    are kept, each with weak references to its series: an identity whose series is gone may be another
    log's."""
    series = tuple(series)
    key = tuple(map(id, series))
    kept = _READINGS.get(key)
    if kept is None or any(ref() is not s for ref, s in zip(kept[0], series)):
        _READINGS.pop(key, None)
        if len(_READINGS) >= READINGS_KEPT:
            _READINGS.pop(next(iter(_READINGS)))
        kept = _READINGS[key] = (tuple(map(weakref.ref, series)), excitation(series), sensor_floor(series))
    return kept[1:]


def _uncertain(p, value: float, stderr: float | None, units, cause) -> str | None:
    """A value whose standard error exceeds ``MAX_RELATIVE_STDERR`` of it: the log does not pin it down, and
    why.  (Temperatures are left out: their relative error depends on where 0 degC is.)"""
    if stderr is None or not np.isfinite(stderr) or p.unit == "degC" or value == 0.0:
        return None
    relative = stderr / abs(value)
    if relative <= MAX_RELATIVE_STDERR:
        return None
    return (f"{p.name} = {plus_minus(value, stderr)}{spaced(p.unit_in(units))}: "
            f"its standard error is {100 * relative:.0f} % of "
            f"it, {cause(p)}")


def _offset_flag(offset_C: float, series: Sequence[ActuatorSeries]) -> str | None:
    measured = np.concatenate([s.temperature_C for s in series])
    ambient = [s.signals.ambient_C for s in series if s.signals.ambient_C is not None]
    if ambient:
        reference, what = float(np.mean(np.concatenate(ambient))), "the logged ambient"
    else:
        reference, what = float(measured.min()), "the coolest reading"
    margin = max(OFFSET_MARGIN_K, 0.5 * float(np.ptp(measured)))
    if abs(offset_C - reference) > margin:
        return (f"T_offset_C = {offset_C:.1f} degC is {abs(offset_C - reference):.0f} K from {what} "
                f"({reference:.1f} degC): other terms stand in for "
                "the heat balance, or heat flows the model lacks")
    return None


UNCERTAIN = re.compile(r"^(\S+) = [^:]*: its standard error is (\d+) % of it, (.+)$")


def said_once(flags) -> list[str]:
    """The flags as a reader takes them: parameters whose standard errors are large for the same reason said
    in one line (``RC_s, betaR_K_per_effort2: standard errors 158 and 107 % of their values, large because the
    model misses something ...``); the JSON keeps each flag whole."""
    groups: dict[str, list] = {}
    for flag in flags:
        m = UNCERTAIN.match(flag)
        if m:
            groups.setdefault(m[3], []).append((m[1], m[2]))
    out, done = [], set()
    for flag in flags:
        m = UNCERTAIN.match(flag)
        if not m or len(groups[m[3]]) == 1:
            out.append(flag)
        elif m[3] not in done:
            done.add(m[3])
            names, shares = zip(*groups[m[3]])
            out.append(f"{', '.join(names)}: standard errors {', '.join(shares[:-1])} and {shares[-1]} % of "
                       f"their values, {m[3]}")
    return out
