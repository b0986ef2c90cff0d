"""One sentence per candidate on what in the data points to it (or does not)."""

from __future__ import annotations

from ...effects import EFFECTS, HOT_AND_COOL, PHASES
from ...model.parameter_units import spaced
from ...model.terms import TERMS
from ...util.numbers import plus_minus
from .candidates import MIN_IMPROVEMENT, SCORE_P_VALUE, Candidate
from .residuals import ResidualAnalysis

# the residual's correlation a log column gives (an effect the catalog does not describe: a user's)
COLUMN_CHANNEL = {"effort": "effort", "velocity": "|velocity|", "current": "current^2", "ambient": "ambient",
                  "power": "power", "housing": "housing temperature"}


def residual_sign(effect: str) -> str | None:
    """What of the residual speaks for ``effect``: its :class:`~thermolimb.effects.Effect`'s, else nothing."""
    known = EFFECTS.get(effect)
    return None if known is None else known.residual


def _channel(effect: str, analysis: ResidualAnalysis) -> str | None:
    for column in TERMS[effect].columns if TERMS[effect].generated else ():
        name = column.removeprefix("extra.")
        for key in (name, column):
            if column.startswith("extra.") and key in analysis.cross:
                return key
    sign = residual_sign(effect)
    if sign is not None:  # a channel, or a neighbour's temperature ("temperature of J1")
        return next((k for k in analysis.cross if k == sign or k.startswith(sign + " ")), None)
    for column in TERMS[effect].columns:
        if COLUMN_CHANNEL.get(column) in analysis.cross:
            return COLUMN_CHANNEL[column]
    return None


def describe(c: Candidate, analysis: ResidualAnalysis, base_rmse: float) -> str:
    if c.confounded:
        return f"confounded: {c.confounded}."
    parts = []
    ph = analysis.phase_rmse_K
    # effects whose signature is in time or temperature, not in an input channel (their terms scale the
    # effort, so the effort's correlation would say nothing about them)
    sign = residual_sign(c.effect)
    channel = _channel(c.effect, analysis) if c.kind != "drop" and sign not in PHASES else None
    if channel:
        corr = analysis.cross[channel]
        lag, value = corr.peak
        peak = f"peak {value:+.2f} at lag {lag:.0f} s, band ±{corr.band:.2f}"
        if corr.significant:
            parts.append(f"the residual correlates with {channel} ({peak})")
        elif c.helps:
            parts.append("no sign of it in the residual's correlation "
                         f"with {channel} alone ({peak}); the score "
                         f"test and the held-out data carry it")
        elif c.p_value is not None and c.p_value < SCORE_P_VALUE:
            parts.append("no sign of it in the residual's correlation "
                         f"with {channel} alone ({peak}); only the "
                         f"score test sees it")
        else:
            parts.append(f"the residual does not correlate significantly with {channel} ({peak})")
    elif sign == HOT_AND_COOL and "hot" in ph and "cool" in ph:
        parts.append(f"the fit is {'worse' if ph['hot'] > ph['cool'] else 'not worse'} when hot "
                     f"(RMSE {ph['hot']:.2f} K hot vs {ph['cool']:.2f} K cool)")
    elif sign in PHASES and sign != HOT_AND_COOL:
        slow = analysis.autocorrelation.values[-1]
        parts.append(f"looking for {sign}: residual autocorrelation {slow:+.2f} "
                     f"at {analysis.autocorrelation.lags_s[-1]:.0f} s, "
                     f"RMSE {ph.get('heating', float('nan')):.2f} K "
                     f"heating vs {ph.get('cool', float('nan')):.2f} K cool")
    if c.kind == "drop":
        parts.append(f"without {c.effect}")
    elif c.kind == "swap":
        parts.append(f"replacing {c.replaces} by {c.effect}")
    else:
        parts.append(f"score test p = {c.p_value:.2g}")
    if c.failure:
        parts.append(f"refit failed: {c.failure}")
        if getattr(TERMS.get(c.effect), "carries_state", False) and (c.improvement or 0.0) >= MIN_IMPROVEMENT:
            parts.append(f"yet the held-out error falls from {base_rmse:.3f} "
                         f"K to {c.rmse_K:.3f} K by where it starts "
                         "its state on each run alone: a run that does "
                         "not begin in a steady state, or a mass slower "
                         "than this log can size (runs from rest long "
                         "enough to show it, or several duties, tell)")
    elif c.refitted:
        if c.kind == "channel":
            parts.append(_fitted(c))
        parts.append(f"validation RMSE goes from {base_rmse:.3f} K to {c.rmse_K:.3f} K")
        if c.units is not None and c.units[1] + _still(c) > 1:
            still = (f" ({_still(c)} more held out near steady state, "
                     "its readings spanning under a tenth of the "
                     f"widest's: no dynamics to judge on)" if _still(c) else "")
            parts.append(f"lower on {c.units[0]} of {c.units[1]} held-out {c.unit_word}{still}"
                         + ("" if 2 * c.units[0] > c.units[1] else ", not most of them: not taken"))
        if c.fragile and (c.improvement or 0.0) > 0.0:  # a change that does not help has no gain to rest on
            parts.append(f"not evidence: {c.fragile}")
        if c.kind == "drop" and c.helps:
            parts.append("the simpler model is no worse on held-out data" if c.improvement < 0.05
                         else "the term extrapolated badly beyond the training data")
        if c.plausible is False:
            parts.append("it fits, but is physically implausible "
                         f"({c.implausible_because}): it stands in for "
                         f"something else")
        if c.identifiable is False:
            parts.append("but this log does not pin its value down")
    return "; ".join(parts) + "."


def _fitted(c: Candidate) -> str:
    """The fitted sizes of a generated term, with their units and uncertainty."""
    return ", ".join(
        f"{name} = {plus_minus(p['value'], p['stderr'])}{spaced(p['unit'])}" for name, p in c.params.items()
    )


def describe_discovered(c: Candidate, proposal, base_rmse: float) -> str:
    """A discovered form's evidence: what it is, how it was chosen, what the refit and held-out data say."""
    parts = [("a discovered form, not a known effect: heat = "
              f"{proposal.formula} ({proposal.words}); chosen by "
              f"sparse regression among {proposal.library_size} library features, it explains "
              f"{100 * proposal.partial_r2:.0f} % of the residual the model cannot")]
    if c.confounded:
        parts.append(f"confounded: {c.confounded}")
    elif c.failure:
        parts.append(f"refit failed: {c.failure}")
    elif c.refitted:
        parts.append(_fitted(c))
        parts.append(f"validation RMSE goes from {base_rmse:.3f} K to {c.rmse_K:.3f} K")
        if c.plausible is False:
            parts.append(f"physically implausible ({c.implausible_because})")
        if c.identifiable is False:
            parts.append("but this log does not pin its value down")
    return "; ".join(parts) + "."


def _still(c) -> int:
    """The held-out units set aside for holding no dynamics (:func:`~.judgement.held_out_support`)."""
    return c.units[2] if len(c.units) > 2 else 0
