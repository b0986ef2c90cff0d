"""One stability replicate (:mod:`.stability`): the search's base, screen and refits on a perturbed copy of
the log, over the changes that contended on the whole log, and the change it takes.

A replicate words no evidence, decides no sensor floor (the whole log's, decided once: a perturbation that
must not matter must not move it), refits no change that brings terms with it unless the whole log found it
eligible, checks no stability and tries no pairs: it answers one question, which change the copy takes.
"""

from __future__ import annotations

from typing import Mapping, Sequence

from ...logs import ActuatorSeries
from ...util.errors import ThermolimbError
from .base_fit import identifiable_base
from .candidates import Candidate
from .refit import refit_all
from .screen import Base, best_eligible, judgeable, rank, screened
from .split_or_blocks import judging_scheme


def replicate(runs: Sequence[ActuatorSeries], model: tuple[str, ...], search, initial: Mapping[str, float],
              specs: Sequence[dict], starts: Sequence[dict]) -> str | None:
    """The label of the change one replicate takes, or ``None``.

    Parameters
    ----------
    runs, search
        The perturbed runs and the search (:class:`~.diagnose.Search`, its scheme perturbed; no stability
        check).
    model, initial
        The whole log's base model and its fitted values, where the replicate's base fit starts.
    specs, starts
        The contenders (:meth:`~.candidates.Candidate.spec`) and where each one's refit starts, in that order.

    Returns
    -------
    The label of the best eligible contender on the replicate, or ``None`` where none is eligible, the
    replicate's held-out data rank nothing, or the copy is too short to split or identifies nothing.
    """
    candidates = [Candidate.from_spec(spec) for spec in specs]
    warm = dict(zip([c.label for c in candidates], starts))
    runs = list(runs)
    scheme = judging_scheme(search.scheme, runs, search.discover)
    try:
        # the replicate's model is the whole log's, its effort levels counted there once
        # (submodel.within_levels)
        base = Base.of(identifiable_base(runs, tuple(model), scheme, initial, search.datasheet, False))
        # a contender built on a term this replicate's base set aside is not the same change here
        candidates = [c for c in candidates if set(c.model) <= {*base.model, c.effect, *c.brings}]
        candidates = screened(candidates, base)
        worth = judgeable(candidates)  # each was refitted on the whole log
        done = refit_all(worth, [warm.get(c.label) for c in worth], runs, scheme, base.report, base.bic, 1)
    except ThermolimbError:  # a copy too short to split, or that identifies nothing: it takes none
        return None
    refitted = {c.label: c for c in done}
    best = best_eligible(sorted((refitted.get(c.label, c) for c in candidates), key=rank))
    return best.label if best is not None and base.report.evidence.rankable else None
