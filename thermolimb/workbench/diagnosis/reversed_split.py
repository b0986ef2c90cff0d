"""The reversed split: on one run, a change must survive the part of the run it was not judged on.

A single run judged by the split fits on its first 70 % and judges a change on its last 30 %, so a change that
explains the run's tail (a regime the tail shares with most of the training part) is never asked to predict
the run's start, where the winding heats from rest -- the part of the run most unlike the tail. Before a
change judged that way is recommended, the model with it and the model without it are both refitted on the
run's last 70 %, each from where its whole fit ended, and each predicts the run's first 30 % from its first
reading (the held-out runs' scheme: the head's first tenth places hidden states and is not scored). A change
whose error there is more than :data:`REFUTED_SHARE` above the model's without it, and above it by more than
the sensor's floor, is refuted by the run's own head and is not recommended; the sentence gives both errors.

Half again, not the 10 % a change must earn: a step of a walk is judged while other physics is still missing,
and the two parts of a run then miss by different amounts whatever the change. On a two-mass plant that hides
speed losses, copper's coefficient and a lagging sensor (``tests/test_diagnosis.py``'s housing friction), the
first step's ``+ speed_losses`` (a true effect) misses the head by 3.68 K where the model without it misses by
3.23 K (14 % worse); a heat that only the tail holds (``tests/test_reversed_split.py``) makes the head
72-109 % worse.
"""

from __future__ import annotations

from ...identification import IdentifiabilityError
from ...logs import LogError
from ..floor import SensorFloor
from ..validation import MIN_RUN_SAMPLES, SPLIT, FitReport, Scheme
from .candidates import Candidate
from .refit import evaluate

REFUTED_SHARE = 0.5  # worse on the head by more than half again


def refuted(change: Candidate, base: FitReport, series, scheme: Scheme,
            floor: SensorFloor | None) -> str | None:
    """Why the run's first part refutes ``change`` (module docstring), or ``None``: not refuted, or not a
    single run judged by the split, or a head or tail too short to fit or judge on, or a refit that cannot be
    made."""
    if scheme.kind != SPLIT or len(series) != 1 or change.report is None:
        return None
    run = series[0]
    try:
        cut = run.split_index(1.0 - scheme.split)
    except LogError:
        return None
    head, tail = run.slice(0, cut), run.slice(cut, run.n)
    if head.n < MIN_RUN_SAMPLES or tail.n < MIN_RUN_SAMPLES:
        return None
    on_head = Scheme.on_runs([head])
    try:
        before = evaluate([tail], base.model.terms, on_head, dict(base.model.params), base.held)
        after = evaluate([tail], change.model, on_head, dict(change.report.model.params), change.report.held)
    except (IdentifiabilityError, LogError):
        return None
    b, a = before.validation["rmse_K"], after.validation["rmse_K"]
    margin = floor.floor_K if floor is not None else 0.0
    if a <= (1.0 + REFUTED_SHARE) * b or a - b <= margin:
        return None
    share = 100 * (1.0 - scheme.split)
    return (f"refuted by the run's first {share:.0f} %: fitted on its last {100 * scheme.split:.0f} %, "
            f"the model with it predicts them at {a:.3f} K, the model without it at {b:.3f} K")
