"""The judgement stage: a refitted change against the base model on the same held-out data -- its held-out
gain and where it comes from, its information criterion, whether it is plausible and identified, and why a
refit failed."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ...effects.effort_bias import carries_the_heat
from ...identification.metrics import chi2_isf, scaled_inverse
from ...model.signals import CHANNELS, EXTRA
from ...model.terms import TERMS, implausibility
from ...util.frozen import FrozenMapping
from ..flags import uncertainty_cause
from .candidates import MIN_IMPROVEMENT, Candidate, bic

WALD_LEVEL = 0.05  # an added effect's size must be jointly non-zero at this level
# a gain must survive leaving out this share of the held-out samples (the most in its favour)
INFLUENTIAL_SHARE = 0.01
MIN_INFLUENTIAL = 3  # ... and at least this many of them
KEPT_GAIN = 0.5  # ... keeping at least this share of the gate (a 10 % gate: 5 % without them)
# a held-out unit whose readings span less than this share of the widest unit's holds no dynamics
STILL_SPAN = 0.1
# a swapped heat source counts as determined where its Wald statistic is this share of the one it replaces
AS_WELL = 0.25


def judge(cand: Candidate, report, base, base_bic: float) -> Candidate:
    """The judgement's record of a refitted change: ``cand`` with the results of its refit
    (:class:`~thermolimb.workbench.validation.FitReport` ``report``), judged against the base model's ``base``
    on the same held-out samples."""
    base_rmse = base.validation["rmse_K"]
    rmse = report.validation["rmse_K"]
    found = dict(report=report, rmse_K=rmse, fit_percent=report.validation["fit_percent"],
                 improvement=1.0 - rmse / base_rmse if base_rmse > 0 else 0.0,
                 delta_bic=bic(report.train_residual_K, len(report.model.params)) - base_bic,
                 flags=tuple(report.flags))
    if cand.kind == "drop":
        return replace(cand, **found, identifiable=True, plausible=True)
    units, robust, fragile = held_out_support(base.validation_segments, report.validation_segments)
    terms, params, channel_units = ([TERMS[t] for t in (*cand.brings, cand.effect)], report.model.params,
                                    report.channel_units)
    handed = (carries_the_heat(params, report.train_series, channel_units)  # this change, not its base, heats
              if not carries_the_heat(base.model.params, base.train_series, channel_units) else None)
    # a change that reads another temperature (a neighbour's, the housing's, the air's) moves what the offset
    # means
    displaced = None if any(map(reads_temperature, terms)) else displaced_offset(report, base)
    reasons = [*(implausibility(t(), params, channel_units) for t in terms), handed, displaced,
               vanished_source(report, base) if cand.adds else None]
    implausible = next(filter(None, reasons), None)
    fitted = {p.name: {"value": params[p.name], "stderr": float(report.stderr[p.name]),
                       "unit": report.unit(p)} for term in terms for p in term.parameters}
    return replace(cand, **found, units=units, robust_improvement=robust, fragile=fragile,
                   unit_word=report.units, implausible_because=implausible,
                   params=FrozenMapping({**cand.params, **fitted}),
                   identifiable=identified(cand, terms, report, base),
                   plausible=implausible is None,
                   failure=next(filter(None, (refit_failure(t, params) for t in terms)), None))


def identified(cand: Candidate, terms, report, base) -> bool:
    """Whether the log determines the change's terms (:func:`term_identified`).  A heat source swapped for
    another is held to what the log shows of the one it replaces: where its Wald statistic is at least
    :data:`AS_WELL` of the base's source's (on a run that only heats, each trades with the time constant
    alike), the swap is judged, as the base is kept, by its held-out error.  On the BLDC bench's full-throttle
    run, whose effort is the electrical power, heat from the power for Joule heating is such a swap (its
    statistic 0.6 of Joule heating's, neither past the test's threshold)."""
    if all(bool(term_identified(t, report)) for t in terms):  # NumPy bools are not ``False``
        return True
    if cand.kind != "swap" or cand.replaces not in base.model.terms:
        return False
    new, old = wald_statistic(TERMS[cand.effect], report), wald_statistic(TERMS[cand.replaces], base)
    return new is not None and old is not None and new >= AS_WELL * old


def wald_statistic(term, report) -> float | None:
    """The Wald statistic of the term's size parameters against their nulls, on the fit's covariance; ``None``
    where the covariance is not finite or a parameter sits on a bound (nothing is determined then)."""
    names = [p.name for p in report.model.parameters]
    primary = [p for p in term.parameters if not p.nuisance]
    idx = [names.index(p.name) for p in primary]
    theta = np.array([report.model.params[p.name] - p.null for p in primary])
    cov = np.asarray(report.estimator.covariance_)[np.ix_(idx, idx)]
    if not np.all(np.isfinite(cov)):
        return None
    for p in primary:
        value = report.model.params[p.name]
        span = p.upper - p.lower if np.isfinite(p.upper - p.lower) else max(abs(value), 1.0)
        if p.lower != p.null and min(abs(value - p.lower), abs(p.upper - value)) < 1e-6 * span:
            return None
    return float(theta @ scaled_inverse(cov) @ theta)


def displaced_offset(report, base) -> str | None:
    """Where a change's refit puts the offset where the workbench's own flags say it cannot be (at a bound, or
    far from the logged ambient or the coolest reading) and the base's fit did not, why the change is
    implausible: it fits by moving the temperature the winding cools to, which the log's other parts refute (a
    motor controller's ``+ sensor_lag`` at T_offset 64 degC, 20 K above the coolest reading, missed its next
    run by 0.282 K where the default model missed it by 0.159 K)."""
    before = {f.split(" = ")[0] for f in base.flags if f.startswith("T_offset_C = ") and _misplaced(f)}
    flag = next((f for f in report.flags if f.startswith("T_offset_C = ") and _misplaced(f)), None)
    if flag is None or "T_offset_C" in before:
        return None
    return f"it moves the offset where it cannot be ({flag.split(': ')[0]})"


def vanished_source(report, base) -> str | None:
    """Where an added effect's refit drives the base model's heat source to its null (the workbench's own
    flag: "vanishes") and the base's fit did not, why the change is implausible: it does not add an effect to
    the heat the model has, it takes that heat's place, and what the log shows of the source is given to
    another input.  On the UR3's J4 (its first part, heating only, one transient) ``+ speed_losses`` cut the
    held-out error from 0.884 to 0.278 K with Joule heating at 6.5e-18 K/(N m)^2, and missed the joint's other
    part by 1.567 K where the default model missed it by 1.057 K (``python benchmarks/transfer.py --sources
    ur3``)."""
    source = next((t for t in base.model.terms if TERMS[t].is_heat_source), None)
    if source is None or source not in report.model.terms:
        return None
    names = {p.name for p in TERMS[source].parameters if not p.nuisance}

    def gone(flags) -> str | None:
        return next((f for f in flags if f.split(" ")[0] in names and f.split(" ", 2)[1] == "vanishes"), None)

    flag = gone(report.flags)
    if flag is None or gone(base.flags) is not None:
        return None
    return f"it takes the place of the model's heat source, not adds to it ({flag.split(': ')[0]})"


def reads_temperature(term) -> bool:
    """Whether ``term`` reads a temperature channel (the ambient, the housing, a neighbour's, a logged
    one)."""
    return any(CHANNELS.get(c, "").endswith("_C") or c.startswith(EXTRA) for c in term.columns)


def _misplaced(flag: str) -> bool:  # the offset's flags that place it, not its uncertainty
    return " is at its bound " in flag or " K from " in flag


def term_identified(term, report) -> bool:
    """Whether the log determines the term: its size parameters are jointly non-zero (a Wald test on their
    covariance, so that two parameters that trade off against each other still count as one effect) and
    none of them sits on a bound."""
    primary = [p for p in term.parameters if not p.nuisance]
    if not primary:
        return True
    wald = wald_statistic(term, report)
    if wald is None:
        return False
    if wald > chi2_isf(WALD_LEVEL, len(primary)):
        return True
    # a model that still fits far worse than the sensor's floor has standard errors inflated by what it
    # misses, not by a lack of excitation: then they say nothing of whether the log determines the term
    misfit, _ = uncertainty_cause(list(report.train_series), report.train["rmse_K"])
    return misfit is not None


def refit_failure(term, params) -> str | None:
    """Why a refit did not find the effect: its size collapsed to the null, or a time constant ran to a
    bound."""
    primary = [p for p in term.parameters if not p.nuisance]
    if primary and all(abs(params[p.name] - p.null) <= 1e-6 * max(abs(p.typical), 1e-12) for p in primary):
        names = ", ".join(f"{p.name} = {p.null:g}" for p in primary)
        return f"collapsed to {names}: the refit found no such effect"
    for p in term.parameters:
        if p.unit == "s":
            for bound in (p.lower, p.upper):
                if np.isfinite(bound) and abs(params[p.name] - bound) <= 1e-3 * max(abs(bound), 1.0):
                    return f"{p.name} ran to its bound {bound:g} s: the log does not show this time scale"
    return None


def held_out_support(base_segments, segments) -> tuple[tuple[int, int, int], float, str | None]:
    """Where a change's held-out gain comes from: on how many held-out units (runs, blocks) it lowers the
    error, of how many that hold dynamics to judge it on, and how many do not (readings spanning under
    :data:`STILL_SPAN` of the widest unit's: a run held near its steady state cannot tell a time constant or a
    neighbour's heat from an offset); the gain left without the few held-out samples most in its favour (the
    :data:`INFLUENTIAL_SHARE` whose squared error it cut most); and, when that falls short of half the gate,
    why it is not evidence."""
    units: dict[str, list] = {}
    spans: dict[str, list] = {}
    for b, c in zip(base_segments, segments):
        pair = units.setdefault(b.unit, [0.0, 0.0])
        pair[0] += float(np.sum((b.measured_C - b.simulated_C) ** 2))
        pair[1] += float(np.sum((c.measured_C - c.simulated_C) ** 2))
        span = spans.setdefault(b.unit, [np.inf, -np.inf])
        span[:] = [min(span[0], float(np.min(b.measured_C))), max(span[1], float(np.max(b.measured_C)))]
    width = {u: hi - lo for u, (lo, hi) in spans.items()}
    widest = max(width.values())
    moving = {u for u in units if width[u] >= STILL_SPAN * widest} or set(units)
    lower = sum(units[u][1] < units[u][0] for u in moving)
    eb = np.concatenate([b.measured_C - b.simulated_C for b in base_segments])
    ec = np.concatenate([c.measured_C - c.simulated_C for c in segments])
    k = max(MIN_INFLUENTIAL, int(np.ceil(INFLUENTIAL_SHARE * eb.size)))
    gain = eb**2 - ec**2
    kept = max(eb.size - k, 1)  # the samples left: those of least gain, picked without sorting them all
    rest = np.argpartition(gain, kept - 1)[:kept] if kept < eb.size else np.arange(eb.size)
    robust = 1.0 - float(np.sqrt(np.sum(ec[rest] ** 2) / max(np.sum(eb[rest] ** 2), 1e-300)))
    fragile = None
    if robust < KEPT_GAIN * MIN_IMPROVEMENT:
        fragile = (f"the held-out gain rests on its {k} most influential "
                   f"samples (of {eb.size}): without them the "
                   f"error falls by {100 * robust:.1f} %, short of {100 * KEPT_GAIN * MIN_IMPROVEMENT:.0f} %")
    return (lower, len(moving), len(units) - len(moving)), robust, fragile
