"""Diagnose a model against a log: residual analysis, ranked changes, a recommendation.

``diagnose(series, model)`` fits the model once (output error, validated by
the chosen :class:`~thermolimb.workbench.validation.Scheme`), analyses its residual,
scores every catalog effect the model lacks, refits the changes worth trying
-- added effects, dropped terms, swapped heat sources -- and recommends the
one that helps most on held-out data, or none.  A change is recommended only
if it is plausible, identifiable, not confounded and its refit did not fail;
candidates are listed best held-out gain first, eligible ones before the rest,
so the first row is the recommendation when there is one.

``auto_diagnose`` walks from the start model: at each step it takes the
recommended change (add, drop or swap), never returning to a model it has
already visited, until nothing helps.

With ``discover=True`` the vocabulary opens (:mod:`.channels`,
:mod:`.discovery`): every extra channel the log carries is tried in the
forms a heat balance allows, and when no change helps and the residual still
has structure, a sparse regression proposes a form the catalog lacks.  Both
are fitted, validated and gated like catalog effects.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Mapping, Sequence

from ...logs import ActuatorSeries
from ...model.terms import DEFAULT_MODEL, parse_model
from ...util.frozen import FrozenMapping
from ...util.parallel import one_blas_thread
from ..flags import said_once
from ..floor import SensorFloor, sensor_floor
from ..validation import FitReport, Scheme
from .base_fit import heat_source_contest, identifiable_base
from .candidates import Candidate
from .discovery import Proposal, proposed
from .explain import describe
from .refit import refits
from .residuals import ResidualAnalysis, analyse_residuals
from .reversed_split import walk_cut
from .screen import Base, best_eligible, changes, rank, screened
from .split_or_blocks import judging_scheme
from .stability import Stability, check
from .together import take_together


@dataclass(frozen=True)
class Search:
    """How a diagnosis looks for what the model misses (``thermolimb diagnose``'s options).

    ``scheme``: how held-out error is measured (:class:`~thermolimb.workbench.validation.Scheme`, held-out
    runs included).  ``refit``: ``"strong"`` refits additions whose score test has p < 0.01 and the three that
    explain most of the residual, and every drop and swap; ``"all"`` refits every candidate.  ``discover``:
    also the log's extra channels, and, when nothing helps and the residual has structure, a discovered form.
    ``datasheet``: values held where the log cannot identify them (``{"RC_s": 600.0}``; see
    :func:`~thermolimb.workbench.submodel.identifiable_submodel`).  ``stability``: before the best change is
    recommended, the search is repeated on perturbed replicates of the log and the change must be taken in
    enough of them (:mod:`.stability`; ``None``: not checked).  ``max_steps``: the most changes ``--auto``
    takes.
    """

    scheme: Scheme = Scheme()
    refit: str = "strong"
    discover: bool = False
    datasheet: Mapping[str, float] = field(default_factory=FrozenMapping)
    stability: Stability | None = None
    max_steps: int = 6
    quiet: bool = True

    def __post_init__(self):
        if self.refit not in ("strong", "all"):
            raise ValueError(f"refit must be 'strong' or 'all', got {self.refit!r}")
        object.__setattr__(self, "datasheet", FrozenMapping(self.datasheet or {}))


@dataclass(frozen=True)
class Step:
    """Where one step of a walk starts: the model already fitted (``base``, a refitted change's report;
    ``None``: fitted here), changes confounded before (``skip``) and models already visited."""

    base: FitReport | None = None
    skip: frozenset = frozenset()
    visited: frozenset = frozenset()


def _search(search: Search | None, options: dict) -> Search:
    return replace(search or Search(), **options) if options else (search or Search())


@dataclass(frozen=True)
class Diagnosis:
    actuator: str
    model: tuple[str, ...]
    base: FitReport
    base_bic: float
    residuals: ResidualAnalysis
    candidates: list[Candidate]
    recommended: Candidate | None
    auto: list[dict] | None = field(default=None)
    proposal: Proposal | None = None  # the discovered form tried, if discovery ran and proposed one
    floor: SensorFloor | None = None  # what the readings can resolve
    stability: dict | None = None  # the replicates' verdicts, when the best change was checked for stability
    # the best change, helping but held back: not taken often enough (stability.steadier), or refuted by the
    # run's part it was not judged on (.reversed_split)
    unstable: Candidate | None = None
    # where a log has both: heat from effort or from current, chosen on held-out data
    heat_source: dict | None = None

    @property
    def at_floor(self) -> bool:
        """The model already explains the log to within the sensor's floor: nothing more is recommended."""
        return self.floor is not None and self.floor.reached(self.base.validation["rmse_K"])

    def to_json(self) -> dict:
        out = {
            "actuator": self.actuator,
            "model": list(self.model),
            "validation_scheme": self.base.scheme,
            "base": {**self.base.validation, "bic": self.base_bic},
            "base_params": self.base.to_json()["params"],
            "channel_units": dict(self.base.channel_units),
            "evidence": self.base.evidence.to_json(),
            "set_aside": [dict(a) for a in self.base.set_aside],
            "flags": list(self.base.flags),
            "flags_said": said_once(self.base.flags),  # as the text says them
            "candidates": [c.to_json() for c in self.candidates],
            "recommended": None if self.recommended is None else self.recommended.effect,
            "recommended_change": None if self.recommended is None else self.recommended.label,
            "recommended_model": None if self.recommended is None else list(self.recommended.model),
            "residuals": self.residuals.to_json(),
            "floor": None if self.floor is None else self.floor.to_json(self.base.validation["rmse_K"]),
            "stability": self.stability,
            "unstable": None if self.unstable is None else self.unstable.label,
            "heat_source": self.heat_source,
        }
        if self.auto is not None:
            out["auto"] = self.auto
        if self.proposal is not None:
            p = self.proposal
            out["proposal"] = {"term": p.term, "formula": p.formula, "words": p.words,
                               "library_size": p.library_size, "partial_r2": p.partial_r2}
        return out


def diagnose(series: Sequence[ActuatorSeries], model=DEFAULT_MODEL, search: Search | None = None,
             **options) -> Diagnosis:
    """Fit ``model``, analyse its residual, rank the changes worth making (module docstring).

    ``search``: how (:class:`Search`); keyword ``options`` replace its fields (``diagnose(runs,
    refit="all")``). A model already within the sensor's floor (:mod:`.floor`) is recommended no change.
    """
    with one_blas_thread():
        return _diagnose(list(series), parse_model(model), _search(search, options), Step())


def _diagnose(series: list[ActuatorSeries], model: tuple[str, ...], search: Search, step: Step) -> Diagnosis:
    """The pipeline: base fit, screen, refits, judgement, stability, verdict (:mod:`.screen`)."""
    search = replace(search, scheme=judging_scheme(search.scheme, series, search.discover))
    heat_source = None
    if step.base is None:
        report = identifiable_base(series, model, search.scheme, None, search.datasheet)
        if not step.visited:
            report, heat_source = heat_source_contest(report, series, search.scheme, search.datasheet)
        model = report.model.terms
    base = Base.of(step.base or report)
    analysis = analyse_residuals(*base.first_run())
    floor = sensor_floor(series, [seg.measured_C - seg.simulated_C for seg in base.report.train_segments])
    at_floor = floor.reached(base.rmse_K)
    candidates = screened(changes(model, base, series, search.discover, search.scheme.held_out, step.skip,
                                  step.visited), base)
    workers = (search.stability or Stability()).workers
    candidates = refits(candidates, base, series, search.scheme, search.refit, workers, search.quiet,
                        floor if at_floor else None)
    candidates = sorted((c if c.evidence else replace(c, evidence=describe(c, analysis, base.rmse_K))
                         for c in candidates), key=rank)
    proposal = None
    if search.discover and best_eligible(candidates) is None and analysis.structured and not at_floor:
        proposal, candidates = proposed(candidates, model, base, series, search.scheme, step.visited)
    rankable = base.report.evidence.rankable  # a handful of held-out readings recommends nothing
    recommended = best_eligible(candidates) if rankable and not at_floor else None
    checked = None
    if recommended is not None and search.stability is not None:
        checked = check(candidates, recommended, model, base.report, series, search)
        candidates = list(checked.candidates)
    if (recommended if checked is None else checked.recommended) is None and not at_floor and rankable:
        candidates, together = take_together(candidates, model, base, series, search, step.visited,
                                             None if checked is None else checked.record)
        checked = together or checked
    if checked is not None:
        recommended = checked.recommended
    return Diagnosis(series[0].actuator, model, base.report, base.bic, analysis, candidates, recommended,
                     proposal=proposal, floor=floor, heat_source=heat_source,
                     stability=None if checked is None else checked.record,
                     unstable=None if checked is None else checked.unstable)


def auto_diagnose(series: Sequence[ActuatorSeries], model=DEFAULT_MODEL, search: Search | None = None,
                  **options) -> tuple[Diagnosis, list[Diagnosis]]:
    """Take the recommended change while one helps, never revisiting a model; returns the first diagnosis and
    every step's.  ``search`` and ``options`` as :func:`diagnose`'s.

    The first diagnosis carries the walk in ``auto``: per step the model, its
    validation error, and the change that led to it with the reason.
    """
    series, search = list(series), _search(search, options)
    with one_blas_thread():
        return _walk(series, parse_model(model), search)


def _walk(series, model, search):
    steps = [_diagnose(series, model, search, Step())]
    visited = {frozenset(steps[0].model)}
    confounded: set[str] = set()
    moves: list[Candidate] = []
    while len(steps) <= search.max_steps:
        d = steps[-1]
        confounded |= {c.label for c in d.candidates if c.confounded}
        move = d.recommended  # eligible, on rankable evidence, above the floor and stable when checked
        if move is None or frozenset(move.model) in visited:
            break
        visited.add(frozenset(move.model))
        moves.append(move)
        steps.append(_diagnose(series, move.model, search, Step(base=move.report, skip=frozenset(confounded),
                                                                visited=frozenset(visited))))
    cut = walk_cut(steps, series, judging_scheme(search.scheme, series, search.discover), steps[0].floor)
    if cut is not None:  # the run's head refutes the end model: back to the last step it does not
        j, why = cut
        held = replace(moves[j], refuted_because=why)
        table = [held if c is moves[j] else c for c in steps[j].candidates]
        steps = steps[:j] + [replace(steps[j], recommended=None, unstable=held, candidates=table)]
        moves = moves[:j]
    waterfall = [_step(d, None if k == 0 else moves[k - 1], steps[k - 1] if k else None)
                 for k, d in enumerate(steps)]
    first, h = steps[0], steps[0].heat_source
    # the walk starts from the effort model, its first step the swap
    if h is not None and h["chosen"] == "current":
        gain = 1.0 - h["current_rmse_K"] / h["effort_rmse_K"]
        waterfall[0].update(change="heat from current", from_rmse_K=h["effort_rmse_K"], improvement=gain,
                            why=f"validation RMSE {h['effort_rmse_K']:.3f} -> {h['current_rmse_K']:.3f} K "
                                f"({-100 * gain:+.1f} %); {h['sentence']}")
        waterfall.insert(
            0,
            {
                "model": h["effort_model"],
                "rmse_K": h["effort_rmse_K"],
                "fit_percent": h["effort_fit_percent"],
                "flags": h["effort_flags"],
                "floor_K": None,
            },
        )
    steps[0] = replace(first, auto=waterfall)
    return steps[0], steps


def _step(d: Diagnosis, move: Candidate | None, before: Diagnosis | None) -> dict:
    out = {"model": list(d.model), "rmse_K": d.base.validation["rmse_K"],
           "fit_percent": d.base.validation["fit_percent"], "flags": list(d.base.flags),
           "flags_said": said_once(d.base.flags),
           "floor_K": None if d.floor is None else d.floor.floor_K}
    if move is not None:
        b = before.base.validation["rmse_K"]
        out.update(change=move.label, from_rmse_K=b, improvement=move.improvement, delta_bic=move.delta_bic,
                   selection_frequency=move.selection_frequency)
        out["why"] = (
            f"validation RMSE {b:.3f} -> {move.rmse_K:.3f} K ({-100 * move.improvement:+.1f} %), "
            f"BIC {move.delta_bic:+.1f}" + (f", {move.stability_sentence}" if move.stability_sentence else "")
        )
    if d.unstable is not None and d.recommended is None:  # where the walk stopped: it helps, held back
        c = d.unstable
        out["unstable"] = {
            "change": c.label,
            "rmse_K": c.rmse_K,
            "selection_frequency": c.selection_frequency,
            "replicates": (d.stability or {}).get("replicates"),
            "why": c.held_back_because,
            "status": c.status,
        }
    if d.at_floor:
        out["at_floor"] = d.floor.sentence(d.base.validation["rmse_K"])
    return out
