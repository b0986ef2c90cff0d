"""The questions a diagnosis leaves open that a designed test can answer (``thermolimb plan --questions``).

Two kinds: parameters of the model's added terms that the log left unsized (a standard error at least
:data:`UNSIZED` of the value: a slow mass's time constant on a short log), and an effect the log could not
tell from a term of the model (confounded at the last step), where a plan can pose it (the effect reads only
what a plan sets: effort, velocity, the air).  ``diagnose --json`` carries them as ``open_questions``; its
text names the ``plan`` command that answers each.
"""

from __future__ import annotations

from dataclasses import dataclass

from ...model.model import BASE_PARAMETERS
from ...model.terms import DEFAULT_MODEL, TERMS

UNSIZED = 0.25  # a time constant or coefficient whose standard error is this share of it, or more, is unsized


@dataclass(frozen=True)
class Questions:
    """One actuator's open questions: the parameters to size (``identify``) and the pair to tell apart
    (``separate``: a term of the model, then the effect confounded with it), for the model ``model``."""

    actuator: str
    model: tuple[str, ...]
    identify: tuple[str, ...] = ()
    separate: tuple[str, str] | None = None

    def to_json(self) -> dict:
        return {"actuator": self.actuator, "model": list(self.model), "identify": list(self.identify),
                "separate": None if self.separate is None else list(self.separate)}

    @classmethod
    def from_json(cls, record: dict) -> "Questions":
        pair = record.get("separate")
        return cls(str(record["actuator"]), tuple(record["model"]), tuple(record.get("identify") or ()),
                   None if not pair else (str(pair[0]), str(pair[1])))


def open_questions(final, last) -> Questions:
    """The questions left by the diagnosis ``last`` (the walk's last step) whose model ``final`` (a
    :class:`~thermolimb.workbench.validation.FitReport`) the user keeps."""
    return Questions(final.actuator, tuple(final.model.terms), tuple(unsized(final)), confounded_pair(last))


def unsized(report) -> list[str]:
    """The parameters of the model's added terms (not the default model's) whose standard error is at least
    :data:`UNSIZED` of their value: what a designed test can size."""
    base = {p.name for p in (*BASE_PARAMETERS, *(q for t in DEFAULT_MODEL for q in TERMS[t].parameters))}
    out = []
    for p in report.model.parameters:
        value, stderr = report.model.params[p.name], report.stderr.get(p.name)
        if p.name in base or stderr is None or not value:
            continue
        if stderr >= UNSIZED * abs(value):
            out.append(p.name)
    return out


def confounded_pair(last) -> tuple[str, str] | None:
    """The first added effect the diagnosis ``last`` found confounded with a term of its model, as ``(term,
    effect)``, where a planned test can pose the question (the effect reads what a plan sets)."""
    from ...experiment import SUPPORTED  # the plan's optimiser, not loaded by a diagnosis that asks nothing

    if last.at_floor:
        return None
    for c in last.candidates:
        if c.kind != "add" or c.brings or not c.confounded or c.effect not in TERMS:
            continue
        if any(col not in SUPPORTED for col in TERMS[c.effect].columns):
            continue
        said = f" {c.confounded} "
        term = next((t for t in last.model if any(f" {p.name} " in said for p in TERMS[t].parameters)), None)
        if term is not None:
            return term, c.effect
    return None
