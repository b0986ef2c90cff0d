"""The scheme a diagnosis judges one run by: the split, unless its held-out tail leaves a channel still.

On one run the default scheme is the split (fit on the first 70 %, judge on the rest; why, in
:mod:`~thermolimb.workbench.validation`).  A change that rides on a channel (velocity, current, a neighbour's
temperature, a logged extra) is judged only where that channel moves (:mod:`~thermolimb.workbench.excitation`),
so a run whose channel moves early and rests in its last 30 % could never have the change judged: a coolant
pump run in bouts during the first hour of two is "not judged" under the split, on every replicate.  Such a run
is judged instead on interleaved blocks, whose held-out blocks span the run, when they hold the channel's
movement; the scheme line says why.  Measured on ``benchmarks/stability.py``'s pump logs (a pump's duty scaling
the conductance, 2 h at 1 Hz, ``--discover``): under the split, nothing taken (the pump "not judged": its duty is
away from its usual level in 23 of the 2160 samples judged on, in one bout); on the blocks, ``+ pump_conductance``.
"""

from __future__ import annotations

from dataclasses import replace

from ...effects import EFFECTS
from ...logs import LogError
from ..excitation import ChannelExcitation, channel_excitation
from ..validation import AUTO, INTERLEAVED, SPLIT, Scheme, scheme_folds


def judging_scheme(scheme: Scheme, series, discover: bool = False) -> Scheme:
    """``scheme`` resolved for ``series`` (:meth:`Scheme.resolved`), with interleaved blocks instead of the split
    where the split's tail leaves still a channel that the rest of the run moves and the blocks' held-out part
    moves (module docstring).  The channels: those the catalog's effects ride on, and with ``discover`` the
    log's extra channels."""
    resolved = scheme.resolved(series)
    if scheme.kind != AUTO or resolved.kind != SPLIT:
        return resolved
    blocked = replace(resolved, kind=INTERLEAVED)
    try:
        tail, blocks = _parts(series, resolved), _parts(series, blocked)
    except LogError:  # too short to hold blocks out: the split, which says so itself if it cannot be made
        return resolved
    for channel in _channels(series, discover):
        split = channel_excitation(channel, *tail)
        if (ChannelExcitation.enough(*split.fitted) and not ChannelExcitation.enough(*split.judged)
                and channel_excitation(channel, *blocks).excited):
            return replace(blocked, why=f"chosen over the split, whose last {100 * (1 - resolved.split):.0f} % "
                                        f"leaves a channel still: {split.sentence()}")
    return resolved


def _parts(series, scheme: Scheme):
    """The one fold of ``scheme`` as :func:`channel_excitation` takes it: the series fitted on, the pieces judged."""
    [(fitted, scored)] = scheme_folds(series, scheme)
    return fitted, [(s.signals.slice(lo, hi), s.temperature_C[lo:hi]) for s, pieces in scored for lo, hi in pieces]


def _channels(series, discover: bool) -> list[str]:
    """The channels every run has that a change could ride on, in the catalog's order, then the extras."""
    ridden = dict.fromkeys(e.rides for e in EFFECTS.values() if e.rides)
    extras = [f"extra.{name}" for name in series[0].signals.extra] if discover else []
    return [c for c in [*ridden, *extras] if all(s.signals.has(c) for s in series)]
