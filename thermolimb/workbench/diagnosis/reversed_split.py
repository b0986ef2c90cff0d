"""The reversed split: on one run, the model a walk ends with must survive the part of the run it was not
judged on.

A single run judged by the split fits on its first 70 % and judges each change on its last 30 %, so a change
that explains the run's tail (a regime the tail shares with most of the training part) is never asked to
predict the run's start, where the winding heats from rest: the part of the run most unlike the tail. When
``diagnose --auto`` has walked, the model it ends with and the model it started from are both refitted on the
run's last 70 %, each from where its fit ended, and each predicts the run's first 30 % from its first reading
(the held-out runs' scheme: the head's first tenth places hidden states and is not scored). Where the end
model's error there is more than :data:`REFUTED_SHARE` above the start's, and above it by more than the
sensor's floor, the walk steps back to the last model that is not; the first change it gives up is held back,
``refuted``, with both errors in its sentence.

The walk's end, not each step, and half again, not the 10 % a change must earn: a step is judged while
other physics is still missing, and a model that lacks it misses the two parts of a run by different amounts
whatever the change (measured in docs/workbench.md, "The run's other part").
"""

from __future__ import annotations

from ...identification import IdentifiabilityError
from ...logs import LogError
from ..floor import SensorFloor
from ..validation import MIN_RUN_SAMPLES, SPLIT, FitReport, Scheme
from .refit import evaluate

REFUTED_SHARE = 0.5  # worse on the head by more than half again


def walk_cut(steps, series, scheme: Scheme, floor: SensorFloor | None) -> tuple[int, str] | None:
    """Where the run's first part cuts a walk of one run judged by the split (module docstring): ``(j, why)``,
    the last step kept and why the change after it is refuted, or ``None`` (nothing refuted, or the check
    cannot be made: not a single run judged by the split, a head or tail too short, a refit that fails).
    ``steps``: the walk's diagnoses, the first one the start."""
    if scheme.kind != SPLIT or len(series) != 1 or len(steps) < 2:
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

    def missed(report: FitReport) -> float:  # its error on the head, fitted on the tail from where it ended
        refitted = evaluate([tail], report.model.terms, on_head, dict(report.model.params), report.held)
        return refitted.validation["rmse_K"]

    try:
        start, errors = missed(steps[0].base), {}
        for j in range(len(steps) - 1, 0, -1):
            errors[j] = missed(steps[j].base)
            if not _worse(errors[j], start, floor):
                break
        else:
            j = 0
    except (IdentifiabilityError, LogError):
        return None
    if j == len(steps) - 1:
        return None
    share = 100 * (1.0 - scheme.split)
    model = ",".join(steps[j + 1].model)
    return j, (f"refuted by the run's first {share:.0f} %: fitted on its last {100 * scheme.split:.0f} %, "
               f"the model with it ({model}) predicts them at {errors[j + 1]:.3f} K, the model the walk "
               f"started from at {start:.3f} K")


def _worse(error_K: float, start_K: float, floor: SensorFloor | None) -> bool:
    margin = floor.floor_K if floor is not None else 0.0
    return error_K > (1.0 + REFUTED_SHARE) * start_K and error_K - start_K > margin
