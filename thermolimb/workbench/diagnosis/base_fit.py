"""The diagnosis's base fit: the start model narrowed to what the log identifies, and, where a log carries
both a torque and a motor current, the contest between heat from either (the better one starts the search)."""

from __future__ import annotations

import numpy as np

from ...model.terms import TERMS
from ...util.errors import ThermolimbError
from ..submodel import identifiable_submodel
from ..validation import FitReport
from .candidates import COLLINEAR
from .judgement import held_out_support
from .refit import evaluate


def heat_source_contest(base: FitReport, series, scheme, datasheet) -> tuple[FitReport, dict | None]:
    """Where a log carries both a torque (effort) and a motor current, heat from effort squared and heat from
    current squared compete on equal footing as the start model's heat source: each fitted and judged on the
    same held-out data (a joint-torque sensor reads gravity load the motor's current may not carry in the same
    proportion).  The better one starts the search; the choice is said with its numbers."""
    model = base.model.terms
    sources = [t for t in model if TERMS[t].is_heat_source]
    squared = {t.squared_channel: name for name, t in TERMS.items() if t.squared_channel}
    joule, by_current = squared.get("effort"), squared.get("current")
    if sources != [joule] or by_current is None or not all(s.signals.has("current") for s in series):
        return base, None
    effort = np.concatenate([s.signals.effort for s in series]) ** 2
    current = np.concatenate([s.signals.current_A for s in series]) ** 2
    if np.ptp(current) == 0 or abs(np.corrcoef(effort, current)[0, 1]) >= COLLINEAR:
        return base, None  # the same heat, or a current that does not move: nothing to choose
    other = tuple(by_current if t == joule else t for t in model
                  if "effort" not in TERMS[t].columns or t == joule)
    try:
        rival = identifiable_base(series, other, scheme, None, datasheet)
    except ThermolimbError:
        return base, None
    e, c = base.validation["rmse_K"], rival.validation["rmse_K"]
    units, _, _ = held_out_support(base.validation_segments, rival.validation_segments)
    current_wins = c < e and 2 * units[0] > units[1]
    (won, won_K, won_word), (lost, lost_K, lost_word) = sorted(
        [(rival, c, "current"), (base, e, "effort")],
        key=lambda x: x[2] != ("current" if current_wins else "effort"),
    )
    lower = units[0] if current_wins else units[1] - units[0]
    sentence = (f"heat source: Joule heating from {won_word} squared "
                f"({','.join(won.model.terms)}), held-out RMSE "
                f"{won_K:.3f} K, against {lost_K:.3f} K from "
                f"{lost_word} squared ({','.join(lost.model.terms)}); "
                f"lower on {lower} of {units[1]} held-out {base.units}")
    # what the effort's model set aside is said even where the current's wins: the walk starts without it
    sentence += "".join(f"; from effort squared, {a['term']} set aside: {a['reason']}" for a in base.set_aside
                        if "term" in a)
    return won, {
        "chosen": won_word,
        "effort_rmse_K": e,
        "current_rmse_K": c,
        "effort_model": list(base.model.terms),
        "current_model": list(rival.model.terms),
        "sentence": sentence,
        "effort_fit_percent": base.validation["fit_percent"],
        "effort_flags": list(base.flags),
    }


def identifiable_base(series, model, scheme, initial, datasheet=None, levels=True) -> FitReport:
    """Fit ``model``, narrowed to what this log identifies (said in the report's ``set_aside``; see
    submodel.py)."""
    return identifiable_submodel(lambda terms, held: evaluate(series, terms, scheme, initial, held),
                                 model, series, datasheet=datasheet, levels=levels)
