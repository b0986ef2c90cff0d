"""What a log shows a thermal model, counted directly: the effort levels it holds, and its heating and cooling
transients.  Large standard errors have two causes a user acts on differently -- a log that does not excite
the model (hold more effort levels, let it heat and cool) and a model that misses something (run
``diagnose``); these counts, with the sensor's floor (:mod:`.floor`), tell them apart."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np

from ..identification.regression import independent_fractions
from ..model.guard import instance
from ..util.errors import ThermolimbError

LEVEL_BINS = 20  # effort levels: the effort's 1-99 % range in this many bins ...
LEVEL_SHARE = 0.02  # ... each holding at least this share of the samples
TRANSIENT_SHARE = 0.1  # a transient rises or falls by this share of the temperature range ...
MIN_TRANSIENT_K = 0.5  # ... and at least this much
MIN_LEVELS, MIN_TRANSIENTS = 3, 2  # a log with fewer does not excite the model
MAX_SAMPLES = 20_000  # transients are counted on every k-th reading of a longer run (they last many samples)


@dataclass(frozen=True)
class Excitation:
    effort_levels: int
    heating: int
    cooling: int

    @property
    def ample(self) -> bool:
        """Enough of each for the first-order model's parameters (three levels pin RC, betaR and a bias)."""
        return not self.lacking()

    def lacking(self) -> list[str]:
        """What the log lacks of :attr:`ample`'s counts, in words (``two cooling transients (it holds
        0)``)."""
        wants = (("three effort levels", self.effort_levels, MIN_LEVELS),
                 ("two heating transients", self.heating, MIN_TRANSIENTS),
                 ("two cooling transients", self.cooling, MIN_TRANSIENTS))
        return [f"{what} (it holds {held})" for what, held, least in wants if held < least]

    def words(self) -> str:
        levels = f"{self.effort_levels} effort level{'s' if self.effort_levels != 1 else ''}"
        transients = "transient" if self.cooling == 1 else "transients"
        return f"{levels}, {self.heating} heating and {self.cooling} cooling {transients}"


def excitation(series) -> Excitation:
    """The counts over every run of ``series``."""
    heating = cooling = 0
    for s in series:
        h, c = _transients(s.temperature_C)
        heating, cooling = heating + h, cooling + c
    return Excitation(effort_levels(series), heating, cooling)


def effort_levels(series) -> int:
    """The effort's distinct levels over every run of ``series``: of :data:`LEVEL_BINS` bins over its 1-99 %
    range, those holding :data:`LEVEL_SHARE` of the samples or more."""
    efforts = np.concatenate([s.signals.effort for s in series])
    lo, hi = np.percentile(efforts, [1, 99])
    if not hi > lo:
        return 1
    counts, _ = np.histogram(np.clip(efforts, lo, hi), bins=LEVEL_BINS, range=(lo, hi))
    return int(np.sum(counts >= LEVEL_SHARE * efforts.size))


def own_shares(series, terms: Sequence[str]) -> dict[str, float] | None:
    """Of the offset's constant and of each of ``terms``' regressors over every run of ``series``, the share
    that the others do not account for (:func:`~thermolimb.identification.regression.independent_fractions`;
    1: its own, 0: a combination of the others', as the effort on two levels makes the effort bias's of Joule
    heating's and the constant): a fit tells a coefficient apart from the others' only by that share.
    ``None`` when a term has no regressor (a form not linear in its parameters)."""
    parts = [[instance(t).features(s.signals, s.temperature_C) for s in series] for t in terms]
    if any(f is None for part in parts for f in part):
        return None
    columns = [np.concatenate([f[:, 0] for f in part]) for part in parts]
    X = np.column_stack([np.ones_like(columns[0]), *columns])
    return dict(zip(("T_offset_C", *terms), map(float, independent_fractions(X))))


def _transients(temperature_C: np.ndarray) -> tuple[int, int]:
    """Rises and falls between turning points, each at least :data:`TRANSIENT_SHARE` of the range (and
    :data:`MIN_TRANSIENT_K`): a zigzag over the readings, a turn confirmed once the reading has come back by
    that much."""
    x = np.asarray(temperature_C, float)
    x = x[:: max(1, x.size // MAX_SAMPLES)]
    threshold = max(MIN_TRANSIENT_K, TRANSIENT_SHARE * float(np.ptp(x)))
    rises = falls = 0
    trend, low, high, extreme = 0, x[0], x[0], x[0]
    for v in x[1:]:
        if trend == 0:
            low, high = min(low, v), max(high, v)
            if v - low >= threshold:
                trend, extreme = 1, v
            elif high - v >= threshold:
                trend, extreme = -1, v
        elif trend == 1:
            if v > extreme:
                extreme = v
            elif extreme - v >= threshold:
                rises, trend, extreme = rises + 1, -1, v
        elif v < extreme:
            extreme = v
        elif v - extreme >= threshold:
            falls, trend, extreme = falls + 1, 1, v
    return rises + (trend == 1), falls + (trend == -1)


# A channel an effect rides on is excited in a part of the data when it is away from rest in at least this
# many samples (and this share of them) -- in two bouts at least, or a tenth of the part: one blip is not
# evidence.
MIN_EXCITED = 30
MIN_EXCITED_SHARE = 0.01
AWAY = 0.05  # away from rest: beyond this share of the channel's 99th percentile of |value| (inputs) ...
# ... or, for a temperature, this far from its median (the neighbours': from this actuator's own)
MOVED_K = 0.5
CHANNEL_WORDS = {"velocity": "the velocity is away from rest", "current": "the current is away from zero",
                 "power": "the power is away from zero", "neighbors": "a neighbour's temperature "
                                                                      "differs by 0.5 K",
                 "ambient": "the ambient moves by 0.5 K", "housing": "the housing's "
                                                                     "temperature moves by 0.5 K"}


@dataclass(frozen=True)
class ChannelExcitation:
    """How much of the data an effect is fitted on and judged on moves the channel it rides on."""

    channel: str
    fitted: tuple[int, int, int]  # samples away from rest, samples, bouts
    judged: tuple[int, int, int]
    # an input away from rest at one level only (|value|): no variation to learn from
    level: float | None = None

    @staticmethod
    def enough(away: int, n: int, bouts: int) -> bool:
        return away >= max(MIN_EXCITED, MIN_EXCITED_SHARE * n) and (bouts >= 2 or away >= 0.1 * n)

    @property
    def excited(self) -> bool:
        return self.enough(*self.fitted) and self.enough(*self.judged) and self.level is None

    def sentence(self) -> str:
        """``the velocity is away from rest in 2 of 4395 samples (2 of 3076 fitted on, in 1 bout; 0 of 1319
        judged on, in 0 bouts); ...``"""
        words = CHANNEL_WORDS.get(self.channel, f"the channel {self.channel.removeprefix('extra.')} "
                                                "is away from "
                                                f"its usual level")
        (a1, n1, b1), (a2, n2, b2) = self.fitted, self.judged
        if self.level is not None and self.enough(*self.fitted) and self.enough(*self.judged):
            return (f"{words} in {a1 + a2} of {n1 + n2} samples, but "
                    f"at one level ({self.level:.4g} in magnitude, "
                    f"within {100 * AWAY:g} % of its largest): a change "
                    "riding on it acts as a constant there, which "
                    f"the model's own terms already are; it needs the channel at two or more levels")
        return (f"{words} in {a1 + a2} of {n1 + n2} samples ({a1} "
                f"of {n1} fitted on, in {b1} bout{'s' * (b1 != 1)}; "
                f"{a2} of {n2} judged on, in {b2} bout{'s' * (b2 != 1)}); at least {MIN_EXCITED} (and "
                f"{100 * MIN_EXCITED_SHARE:g} %) in two bouts are needed in each")


def channel_excitation(channel: str, fitted, judged) -> ChannelExcitation:
    """How much ``channel`` (a log column: ``velocity``, ``current``, ``neighbors``, ``extra.NAME``, ...)
    moves in the samples a change is fitted on (``fitted``: series, each fitted on its ``fit_mask``) and
    judged on (``judged``: :class:`~thermolimb.model.Signals` of the held-out pieces, with their measured
    temperatures)."""
    fit_parts = [(s.signals, s.temperature_C, s.fit_mask) for s in fitted]
    judged_parts = [(signals, temperature_C, None) for signals, temperature_C in judged]
    values = _moved(channel,
                    [(signals, temperature_C) for signals, temperature_C, _ in fit_parts + judged_parts])
    scale = _scale(channel, values)
    counts = []
    for parts, moved in ((fit_parts, values[:len(fit_parts)]), (judged_parts, values[len(fit_parts):])):
        away = n = bouts = 0
        for (_, _, mask), x in zip(parts, moved):
            on = x > scale
            if mask is not None:
                on, n_part = on[mask], int(np.count_nonzero(mask))
            else:
                n_part = x.size
            away, n = away + int(np.count_nonzero(on)), n + n_part
            bouts += int(np.count_nonzero(np.diff(np.r_[0, on.astype(np.int8)]) == 1))
        counts.append((away, n, bouts))
    return ChannelExcitation(channel, counts[0], counts[1], _one_level(channel, values, scale))


def _one_level(channel: str, moved: list[np.ndarray], scale: float) -> float | None:
    """The level an input holds wherever it is away from rest, when its 5th to 95th percentiles there lie
    within the rest threshold of each other (PMSM profile 24 spins at 576 rad/s throughout but its first five
    samples; cut by a few rows at its start, motion cooling fitted there as a second conductance and was taken
    in 9 of 10 replicates, ``benchmarks/stability.py``); else ``None``.  Temperatures and extra channels are
    left to their counts."""
    if (
        channel in ("neighbors", "ambient", "housing")
        or channel.startswith("extra.")
        or not np.isfinite(scale)
    ):
        return None
    on = np.concatenate([x[x > scale] for x in moved]) if moved else np.zeros(0)
    if on.size == 0:
        return None
    low, high = np.percentile(on, [5, 95])
    return float(np.median(on)) if high - low <= scale else None


def _moved(channel: str, parts) -> list[np.ndarray]:
    """How far each sample of ``channel`` is from rest, per part: |value| for an input, the distance from the
    whole data's median for a temperature or an extra channel, the neighbours' mean's distance from this
    actuator's own reading."""
    if channel == "neighbors":
        return [np.abs(signals.neighbor_mean_C - temperature_C) for signals, temperature_C in parts]
    values = [np.asarray(signals.channel(channel), float) for signals, _ in parts]
    if channel in ("ambient", "housing") or channel.startswith("extra."):
        middle = float(np.median(np.concatenate(values)))
        return [np.abs(x - middle) for x in values]
    return [np.abs(x) for x in values]


def _scale(channel: str, moved: list[np.ndarray]) -> float:
    """Beyond this, a sample is away from rest (module constants)."""
    if channel in ("neighbors", "ambient", "housing"):
        return MOVED_K
    whole = np.concatenate(moved) if moved else np.zeros(1)
    top = float(np.percentile(whole, 99)) if whole.size else 0.0
    # a channel at rest nearly always: its largest
    top = top if top > 0 else float(np.max(whole, initial=0.0))
    return AWAY * top if top > 0 else np.inf


def refuse_flat(runs: list, name: str) -> None:
    """An actuator whose temperature reads one value on every sample is refused in one sentence (no model is
    identified from it); at zero effort throughout, most likely a motor the robot's table lists but nothing
    drives (a Unitree low-state table's unused slots read 0 degC and 0 N m)."""
    values = np.concatenate([r.temperature_C for r in runs]) if runs else np.empty(0)
    if values.size == 0 or np.ptp(values) > 0:
        return
    idle = not any(np.any(r.signals.effort) for r in runs)
    why = (
        " and its effort 0 throughout: a motor that is not connected, or a slot the logger fills in"
        if idle
        else ""
    )
    raise ThermolimbError(f"the temperature of {name} reads {values[0]:g} "
                          f"degC on every one of its {values.size} "
                          f"samples{why}; a model needs a temperature that changes")


def refuse_disturbed(runs: list, name: str) -> None:
    """An actuator whose readings fall as its effort steps up and jump as it steps down
    (:func:`~thermolimb.logs.suspect.disturbed_spans`) is refused in one sentence naming the intervals: a
    model fitted through them would take the heat going in for cooling (a time constant of days)."""
    from ..logs.suspect import disturbed_spans

    found = [(run, a, b, fall, jump) for run in runs
             for a, b, fall, jump in disturbed_spans(run.temperature_C, run.signals.effort)]
    if not found:
        return
    run, a, b, fall, jump = found[0]
    t = run.time_s
    where = "; ".join(
        f"{r.run + ': ' if r.run else ''}{r.time_s[x]:g} s to {r.time_s[y - 1]:g} s"
        for r, x, y, _, _ in found[:4]
    ) + (f" and {len(found) - 4} more" if len(found) > 4 else "")
    raise ThermolimbError(
        f"the temperature of {name} reads low while it is driven: "
        + (f"it falls by {fall:.1f} K as the effort steps up at {t[a]:g} s and " if fall >= 1.0 else "it ")
        + f"jumps by {jump:.1f} K as the effort steps down at {t[b]:g} s, against the heat put in (a sensor "
        "disturbed by the drive, e.g. its electromagnetic "
        f"noise); driven intervals read so: {where}. A model "
        "fitted through them would take heating for cooling, "
        "so none is fitted: log the sensor with the drive's "
        f"noise filtered or shielded, or give runs whose readings are taken with the drive off")


def refuse_unfittable(runs: list, name: str) -> None:
    """What no model is fitted from, refused in one sentence: a temperature that never changes
    (:func:`refuse_flat`), or one that reads low while the actuator is driven (:func:`refuse_disturbed`)."""
    refuse_flat(runs, name)
    refuse_disturbed(runs, name)
