"""Two effects that help only together: where the walk would stop, pairs of the additions the training data
want.

The walk takes one change at a time, each judged on held-out data.  Two effects can each fail that alone and
help together: on the plant's two-mass X8 knee with speed losses, copper's coefficient and a lagging sensor
hidden (the forecast benchmark's seed-0 calibration log, ``docs/model-file.md``'s ``cal.csv``), ``+
speed_losses`` alone lowers the held-out error by 15 % and is taken in 6 of 10 replicates, and ``+
second_node`` alone raises it by 32 %: the speed losses fitted without the housing misplace the heat, and the
mass fitted without them has no heat to store. Together they take it from 5.169 to 0.931 K.  At the end of
that walk ``+ sensor_lag`` and ``+ winding_tempco`` each fail alone (-1.6 % and -48.5 %) where together they
reach the sensor's floor.

So where a step recommends nothing (no eligible change, or the best one unstable), the additions the training
data want (a catalog effect refitted alone, plausible, its BIC lower than the model's) are tried in pairs, the
:data:`MEMBERS` strongest by BIC, each pair refitted once from where its better member ended, with the other's
values from its own refit.  A pair is kept only if it beats each member alone by the held-out gate
(:data:`~.candidates.MIN_IMPROVEMENT`): both are needed.  It is then judged like any change (its label ``+ A
with B``) and checked on the same replicates, but taken only where every replicate takes it
(:data:`PAIR_FREQUENCY`; the order rule, ``stability.in_some_order``, does not lower that, and the pair's line
says so): it is the best of a search over combinations, each member of which failed alone, and stability
selection asks a higher share where more is searched (Meinshausen and Buhlmann, 2010, bound the false
selections by the number searched).  At the 0.8 a single change needs, both runs of the UR3's J0 took ``+
speed_losses with neighbor_coupling`` (0.880 -> 0.161 K held out) in 15 of 20 replicates, and one of four
copies of the log cut by a few rows took it (``benchmarks/stability.py --only "UR3 J0"``: 75 % the same
verdict; 100 % with every replicate asked, where 7 of 10 take it).
"""

from __future__ import annotations

from dataclasses import replace
from itertools import combinations

from ...model.terms import TERMS
from .candidates import MIN_IMPROVEMENT, Candidate
from .refit import refit_candidate
from .screen import Base, rank
from .stability import Checked, check

MEMBERS = 3  # the strongest additions by BIC paired: at most three refits where a step would stop
PAIR_FREQUENCY = 1.0  # a pair is taken only where every replicate takes it (module docstring)


def pairs(candidates: list[Candidate], model: tuple[str, ...], series, scheme, base, base_bic: float,
          visited: frozenset, checked: bool = False) -> list[Candidate]:
    """The pairs of additions that help together and beat each member alone by the gate, refitted and judged
    (``checked``: their lines say what the stability check will ask of them)."""
    members = sorted(
        (
            c
            for c in candidates
            if c.kind == "add"
            and not c.brings
            and c.refitted
            and c.failure is None
            and c.confounded is None
            and c.unexcited is None
            and c.broken is None
            and c.plausible is not False
            and c.identifiable is not False
            and c.delta_bic < 0
        ),
        key=lambda c: c.delta_bic,
    )[:MEMBERS]
    kept = []
    for a, b in combinations(members, 2):
        # the better alone first: the pair starts where it ended
        a, b = sorted((a, b), key=lambda c: c.rmse_K)
        both = model + (a.effect, b.effect)
        if frozenset(both) in visited:
            continue
        pair = Candidate(b.effect, both, brings=(a.effect,))
        own = {p.name for p in TERMS[b.effect].parameters}
        start = {**a.report.model.params, **{k: v for k, v in b.report.model.params.items() if k in own}}
        pair = refit_candidate(pair, series, scheme, base, base_bic, start)
        if pair.refitted and pair.rmse_K <= (1.0 - MIN_IMPROVEMENT) * a.rmse_K:
            kept.append(replace(pair, evidence=(
                f"together: {a.label} alone {a.rmse_K:.3f} K, {b.label} alone {b.rmse_K:.3f} K held out; "
                f"validation RMSE goes from {base.validation['rmse_K']:.3f} K to {pair.rmse_K:.3f} K"
                + (f"; a pair is taken only where {_share()} takes it." if checked else "."))))
    return kept


def _share() -> str:  # what the check asks of a pair, in words
    return "every replicate" if PAIR_FREQUENCY >= 1.0 else f"{PAIR_FREQUENCY:.0%} of the replicates"


def take_together(candidates: list[Candidate], model: tuple[str, ...], base: Base, series, search,
                  visited: frozenset, alone: dict | None) -> tuple[list[Candidate], Checked | None]:
    """Where a diagnosis recommends nothing: its ``candidates`` (ranked) with the pairs (:func:`pairs`) among
    them, and the verdict where one is eligible (else ``None``: the verdict stands), checked by the stability
    check when the search checks, at :data:`PAIR_FREQUENCY`; ``alone`` is the check's record of the changes
    alone, kept in the new record as ``"alone"``."""
    found = pairs(candidates, model, series, search.scheme, base.report, base.bic, visited,
                  search.stability is not None)
    if not found:
        return candidates, None
    candidates = sorted(candidates + found, key=rank)
    best = next((c for c in sorted(found, key=rank) if c.eligible), None)
    if best is None:
        return candidates, None
    if search.stability is None:
        return candidates, Checked(alone, best, None, tuple(candidates))
    first = {c.label: c.selection_frequency for c in candidates}
    # the check decides again with the pairs among the contenders; what the first said of a change it does not
    # re-judge stays in that change's words
    again = replace(search, stability=replace(search.stability, min_frequency=PAIR_FREQUENCY))
    cleared = [replace(c, selection_frequency=None) for c in candidates]
    checked = check(cleared, best, model, base.report, series, again, False)
    candidates = list(checked.candidates)
    if alone is not None:
        same = alone["replicates"] == checked.record["replicates"]  # and its share, where both ran as many
        candidates = [replace(c, selection_frequency=first.get(c.label))
                      if c.selection_frequency is None and same else c for c in candidates]
        checked = replace(checked, record={**checked.record, "alone": alone}, candidates=tuple(candidates))
    return candidates, checked
