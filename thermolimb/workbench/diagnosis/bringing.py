"""A change that brings terms the model lacks with it: a channel's form with the slow mass it acts on, or a
third mass with the second (two masses at once).

Each costs more parameters at once, so each is refitted only where the simpler change it grows from tells it
to:

* **a mass with a channel's form** only where no simpler change helps;
* **two masses at once** only where the second mass alone helps but fits implausibly, its share of the rise
  past what one mass can hold: it stands in for two.  On a plant richer than the model (the X8's winding,
  housing and body, 1.4, 24.5 and 10,100 s), squatting for 2 h, `+ second_node` alone takes the held-out error
  from 8.53 to 2.24 K at a share of 0.957 (plausible up to 0.95), and the walk, one change at a time, could
  not reach the third mass without it: with both, 0.81 K, and the walk's model predicts the plant's other
  duties at 12.3 K where Jorgensen et al.'s misses by 40.1 K (``python benchmarks/transfer.py --sources
  plant``).  The pair starts where the mass alone ended, the other at its typical values: one refit, not the
  profile's search (which reaches 0.797 K there, at the cost of several), and one that finds no second mass is
  said as failed (``refit.py``).  On the bundled real logs no walk's verdict moves (``--sources
  ur3,wx200,bldc,pmsm``); where a UR3 joint's mass alone is implausible (J5's second part, a share of 0.98)
  the pair's one refit adds a third to its walk's time.
"""

from __future__ import annotations

from ...model.terms import TERMS
from .candidates import Candidate


def not_brought(cand: Candidate, worth: list[Candidate]) -> str | None:
    """Why ``cand``, a change that brings terms with it, is not refitted (None: it is), ``worth`` being the
    simpler changes refitted before it."""
    if cand.kind == "add":
        alone = _alone(cand, worth)
        if alone is None or alone.status != "implausible" or not alone.helps:
            return f"a mass with another is tried only where {cand.brings[0]} alone helps, implausibly"
        return None
    simpler = next((c for c in worth if c.eligible), None)
    if simpler is not None:
        return f"a simpler change helps ({simpler.label}); a mass with a channel is tried only without one"
    return None


def brought_start(cand: Candidate, worth: list[Candidate]) -> dict | None:
    """Where two masses at once start: the mass alone's refit, the other at its typical values."""
    alone = _alone(cand, worth) if cand.kind == "add" else None
    if alone is None or alone.report is None:
        return None
    return {**alone.report.model.params, **{p.name: p.typical for p in TERMS[cand.effect].parameters}}


def _alone(cand: Candidate, worth: list[Candidate]) -> Candidate | None:
    return next((c for c in worth if c.kind == "add" and c.effect == cand.brings[0] and not c.brings), None)
