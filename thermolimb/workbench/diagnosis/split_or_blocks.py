"""The scheme a diagnosis judges one run by: the split, unless its held-out tail leaves a channel or the heat
still.

On one run the default scheme is the split (fit on the first 70 %, judge on the rest; why, in
:mod:`~thermolimb.workbench.validation`).  A change that rides on a channel (velocity, current, a neighbour's
temperature, a logged extra) is judged only where that channel moves
(:mod:`~thermolimb.workbench.excitation`), so a run whose channel moves early and rests in its last 30 % could
never have the change judged: a coolant pump run in bouts during the first hour of two is "not judged" under
the split, on every replicate.  Such a run is judged instead on interleaved blocks, whose held-out blocks span
the run, when they hold the channel's movement; the scheme line says why.  Measured on
``benchmarks/stability.py``'s pump logs (a pump's duty scaling the conductance, 2 h at 1 Hz, ``--discover``):
under the split, nothing taken (the pump "not judged": its duty is away from its usual level in 23 of the 2160
samples judged on, in one bout); on the blocks, ``+ pump_conductance``. A run whose tail holds the heat input
still (a step test cooled to rest, PMSM profile 24's last stretch at one torque and one current) is judged on
the blocks too (:func:`still_tail`), and the blocks are placed where a held-out one holds a step of the heat
input (:func:`placed`).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ...effects import EFFECTS
from ...logs import LogError
from ..excitation import ChannelExcitation, channel_excitation
from ..validation import AUTO, INTERLEAVED, INTERLEAVED_BLOCKS, SPLIT, Scheme, held_blocks, scheme_folds

# a step of the heat input: its mean effort squared changes by half its range (1st-99th percentile)
STEP_SHARE = 0.5
# a split's tail holds the effort still where its square spans under this share of the run's
STILL_SHARE = 0.1
# where the block grid may be moved to, in blocks: over one period of the held-out pattern (every third
# block), so that any step after the first block can be held; never earlier than half a block (the first
# held-out block then starts half a block into the run at least, as the replicates' moves allow)
PHASES = np.linspace(-0.5, 1.5, 41)


def judging_scheme(scheme: Scheme, series, discover: bool = False) -> Scheme:
    """``scheme`` resolved for ``series`` (:meth:`Scheme.resolved`), with interleaved blocks instead of the
    split where the split's tail leaves still a channel that the rest of the run moves and the blocks'
    held-out part moves (module docstring).  The channels: those the catalog's effects ride on, and with
    ``discover`` the log's extra channels."""
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
            why = (
                f"chosen over the split, whose last {100 * (1 - resolved.split):.0f} % leaves a channel "
                "still: "
                f"{split.sentence()}"
            )
            return placed(replace(blocked, why=why), series)
    still = still_tail(series, resolved.split)
    if still is not None:
        tail = f"{100 * (1 - resolved.split):.0f} %"
        why = f"chosen over the split, whose last {tail} holds the heat input still: {still}"
        return placed(replace(blocked, why=why), series)
    return resolved


def still_tail(series, split: float) -> str | None:
    """Why the split's tail of every run holds the heat input still while the rest of the run moves it, or
    ``None``: the effort squared, and the current squared where the log has it, span under :data:`STILL_SHARE`
    of the run's span there (1st to 99th percentile).  A tail at rest after a step test's release shows no
    dynamics for a change to be judged on: a step test that logs no current (``benchmarks/transfer.py``'s hold
    at 1.5, its current column left out) was judged on its last 30 %, six distinct readings of a joint cooled
    to rest, where two slow masses "did not help" (0.940 against 0.418 K)."""
    spans = {}
    for s in series:
        cut = int(np.searchsorted(s.time_s, s.time_s[0] + split * (s.time_s[-1] - s.time_s[0])))
        for channel in ("effort", "current"):
            if channel == "current" and not s.signals.has("current"):
                continue
            x = np.asarray(s.signals.channel(channel), dtype=float) ** 2
            whole = np.ptp(np.percentile(x, [1, 99]))
            tail = np.ptp(np.percentile(x[cut:], [1, 99])) if cut < x.size else 0.0
            if whole <= 0.0 or tail >= STILL_SHARE * whole:
                return None
            spans[channel] = max(spans.get(channel, 0.0), tail / whole)
    said = " and ".join(f"the {c}'s square spans {100 * v:.1g} %" for c, v in spans.items())
    return f"{said} of the run's there, so no step of the heat input is held out to judge a change on"


def placed(scheme: Scheme, series) -> Scheme:
    """The interleaved ``scheme`` with its block grid moved so that a held-out block holds a step of the heat
    input within its middle half, where at its place none does, and said in its line: a held-out block must
    hold the dynamics a change claims to explain.  A step test (a load held, then released) has one such step
    after its first block; blocks 2, 5, 8 of 10 held the release of the plant's 1.5 x step test 20 s before a
    held block's end (``benchmarks/transfer.py --sources step``), so whether its housing's heat was judged at
    all hung on the replicates' moving the grid (+ second mass taken in 5 of 10). Only the input's steps place
    it (no reading does); a log whose held-out blocks already hold a step, as a duty of many moves does, keeps
    its grid."""
    steps = [(s.time_s[0], s.time_s[-1] - s.time_s[0], t) for s in series for t in input_steps(s)]
    if not steps:
        return scheme

    def held(phase: float) -> tuple[int, float]:
        """How many steps lie in a held-out block's middle half, and how near the middles they lie."""
        inside, off = 0, 0.0
        for t0, span, t in steps:
            position = (t - t0) / max(span, 1e-12) * INTERLEAVED_BLOCKS - phase
            if int(np.floor(position)) in held_blocks() and 0.25 <= position % 1.0 <= 0.75:
                inside, off = inside + 1, off + abs(position % 1.0 - 0.5)
        return inside, off

    if held(scheme.phase)[0] > 0:
        return scheme
    best = min(PHASES, key=lambda p: (-held(p)[0], held(p)[1], abs(p)))
    count = held(best)[0]
    if count == 0:
        return scheme
    at = ", ".join(f"{t - t0:.0f} s" for t0, span, t in steps)
    return replace(scheme, phase=float(best), why=f"{scheme.why}; the blocks moved "
                                                  f"by {best:+.2f} of a block so that "
                   f"held-out ones hold {count} of the effort's "
                   f"{len(steps)} step(s) (at {at}) in their middle half, "
                   f"where they held none")


def input_steps(s) -> list[float]:
    """When the heat input steps after a run's first block: the mean effort squared over a fifth of a block
    after an instant differs from that over a fifth before by :data:`STEP_SHARE` of its range; one time a
    step."""
    x = np.asarray(s.signals.effort, dtype=float) ** 2
    t = s.time_s
    if x.size < 10:
        return []
    width = max(1, int(round(x.size / INTERLEAVED_BLOCKS / 5)))
    sums = np.concatenate([[0.0], np.cumsum(x)])
    k = np.arange(width, x.size - width + 1)
    jump = np.abs((sums[k + width] - sums[k]) - (sums[k] - sums[k - width])) / width
    low, high = np.percentile(x, [1, 99])
    big = jump > STEP_SHARE * max(high - low, 1e-12)
    out, k_big = [], k[big]
    for group in np.split(k_big, np.flatnonzero(np.diff(k_big) > width) + 1) if k_big.size else []:
        at = group[np.argmax(jump[group - width])]
        if (t[at] - t[0]) / max(t[-1] - t[0], 1e-12) * INTERLEAVED_BLOCKS >= 1.0:
            out.append(float(t[at]))
    return out


def _parts(series, scheme: Scheme):
    """The one fold of ``scheme`` as :func:`channel_excitation` takes it: the series fitted on, the pieces
    judged."""
    [(fitted, scored)] = scheme_folds(series, scheme)
    return fitted, [
        (s.signals.slice(lo, hi), s.temperature_C[lo:hi]) for s, pieces in scored for lo, hi in pieces
    ]


def _channels(series, discover: bool) -> list[str]:
    """The channels every run has that a change could ride on, in the catalog's order, then the extras."""
    ridden = dict.fromkeys(e.rides for e in EFFECTS.values() if e.rides)
    extras = [f"extra.{name}" for name in series[0].signals.extra] if discover else []
    return [c for c in [*ridden, *extras] if all(s.signals.has(c) for s in series)]
