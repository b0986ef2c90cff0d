"""Fit on part of the data, validate by free-run simulation on the rest.

Every command (``fit``, ``compare``, ``diagnose``) validates the same way, each run simulated from its own
first reading, chosen by a :class:`Scheme`; the default is **leave one run out** with several runs, else the
**split**:

* a **split**: fit on the first ``split`` (70 %) of each run; the free run starts at the run's beginning and
  runs through the training part into the held-out part, scored on the latter only, so hidden states (a slow
  mass, a lagging sensor) arrive there as they really are (``restart``: from the measured temperature
  instead);
* **interleaved blocks** (``interleaved``): every third of ten blocks held out, heating and cooling alike;
* **leave one part out** (``parts``): each of three parts held out in turn;
* **blocked cross-validation** over ``folds`` contiguous blocks; **leave one run out**: each run validated,
  whole, by a model fitted on the other runs; **held-out runs**: fit on the runs given, validate on others.

Why the split on one run: ``python benchmarks/transfer.py --sources ur3,wx200,bldc,pmsm`` fits the walk's
model on one run and scores it on the joint's other runs (18 real cases).  The split made the model better
there in 5 cases and worse in 1 (6.7 s a walk); 30 interleaved blocks 1 and 2; leave one part out 3 and 2 at
40 s a walk.  A diagnosis takes interleaved blocks where the split's tail leaves a channel still
(``diagnosis.split_or_blocks``)."""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Callable, Mapping, Sequence

import numpy as np

from ..identification import ESTIMATORS, ThermalEstimator
from ..identification.metrics import pieces_metrics
from ..logs import MIN_SAMPLES, ActuatorSeries, LogError
from ..model.experience import air_words, ambient_shift_K, ambient_span, common_air, moved_words, shifted
from ..model.model import ThermalModel
from ..model.signals import Signals
from ..model.terms import parse_model
from .carry import carry_flags
from .evidence import Evidence
from .flags import parameter_flags, said_once
from .submodel import identifiable_submodel

AUTO, INTERLEAVED, SPLIT, BLOCKS, RUNS, PARTS, HELD_OUT = (
    "auto",
    "interleaved",
    "split",
    "blocks",
    "runs",
    "parts",
    "held_out",
)
KINDS = (AUTO, INTERLEAVED, SPLIT, BLOCKS, RUNS, PARTS, HELD_OUT)
# leave one part out: one run's time span in this many parts, each predicted from the others
PARTS_OF_A_RUN = 3
INTERLEAVED_BLOCKS = 10  # an interleaved scheme cuts each run's time span into this many blocks ...
HELD_EVERY = 3  # ... and holds out every third of them, from the second: blocks 2, 5 and 8 of 10
MIN_RUN_SAMPLES = 2 * MIN_SAMPLES  # a run shorter than this cannot carry a fold of its own
# a held-out run's first tenth of its time span places its hidden states (a slow mass, the winding behind a
# lagging sensor) and is not scored: every model is judged on the rest, from the same first sample
BURN_IN_SHARE = 0.1


@dataclass(frozen=True)
class Scheme:
    """How held-out error is measured: one :data:`KINDS` (see the module docstring) and what it needs.

    ``Scheme.at_split(0.7)``, ``Scheme.in_blocks(5)``, ``Scheme.leave_one_run_out()``,
    ``Scheme.on_runs(held_out)``; every output names the scheme in one line (:meth:`describe`).
    """

    kind: str = AUTO
    split: float = 0.7  # SPLIT: the share of each run's time span fitted on
    folds: int = 5  # BLOCKS: contiguous blocks of each run
    parts: int = PARTS_OF_A_RUN  # PARTS: contiguous parts of each run, each held out whole in turn
    restart: bool = False  # SPLIT, BLOCKS: the free run restarts at the held-out part, hidden states at rest
    held_out: tuple = ()  # HELD_OUT: the runs validated on (ActuatorSeries)
    phase: float = 0.0  # INTERLEAVED: the block grid shifted by this share of a block (stability replicates)
    why: str = ""  # why it was chosen over the default, said after it (diagnosis.split_or_blocks)

    def __post_init__(self):
        if self.kind not in KINDS:
            raise ValueError(f"a validation scheme is one of {', '.join(KINDS)}, got {self.kind!r}")
        if not 0.0 < self.split < 1.0:
            raise LogError(f"--split must be between 0 and 1 (exclusive), got {self.split}")
        if self.kind == BLOCKS and self.folds < 2:
            raise LogError(f"--cv needs at least 2 folds (or 'runs'), got {self.folds}")
        if self.kind == HELD_OUT and not self.held_out:
            raise ValueError("a scheme of held-out runs needs the runs")
        object.__setattr__(self, "held_out", tuple(self.held_out))

    @classmethod
    def interleaved(cls) -> "Scheme":
        return cls(INTERLEAVED)

    def resolved(self, series) -> "Scheme":
        """The scheme for these runs: ``auto`` is leave one run out when the actuator has several runs (each
        long enough to be fitted on), interleaved blocks of its one run otherwise; any other kind is
        itself."""
        if self.kind != AUTO:
            return self
        several = len(series) >= 2 and all(s.n >= MIN_RUN_SAMPLES for s in series)
        return replace(self, kind=RUNS if several else SPLIT)

    @classmethod
    def at_split(cls, split: float = 0.7, restart: bool = False) -> "Scheme":
        return cls(SPLIT, split=split, restart=restart)

    @classmethod
    def in_blocks(cls, folds: int, restart: bool = False) -> "Scheme":
        return cls(BLOCKS, folds=folds, restart=restart)

    @classmethod
    def leave_one_run_out(cls) -> "Scheme":
        return cls(RUNS)

    @classmethod
    def on_runs(cls, held_out) -> "Scheme":
        return cls(HELD_OUT, held_out=tuple(held_out))

    def describe(self) -> str:
        return f"{self._words()}; {self.why}" if self.why else self._words()

    def _words(self) -> str:
        if self.kind == HELD_OUT:
            return "fitted on the given runs, validated on the held-out runs"
        if self.kind == RUNS:
            return ("leave one run out: each run predicted from its first reading by the model fitted on the "
                    "others")
        if self.kind == PARTS:
            return (f"leave one part out: each run in {self.parts} "
                    "parts, each predicted from its first reading by the "
                    f"model fitted on the others")
        if self.kind == INTERLEAVED:
            held = ", ".join(str(b + 1) for b in held_blocks())
            return (f"interleaved blocks: blocks {held} of "
                    f"{INTERLEAVED_BLOCKS} of each run held out, the free run "
                    f"carried from the run's start through them")
        if self.kind == AUTO:
            return "leave one run out with several runs, a split of one run otherwise"
        if self.kind == BLOCKS:
            start = "restarted at each block" if self.restart else "free run carried from each run's start"
            return f"{self.folds}-fold blocked cross-validation, {start}"
        start = "restarted at the split" if self.restart else "free run carried from each run's start"
        return f"fit on the first {100 * self.split:.0f} % of each run, {start}"


def held_blocks() -> list[int]:
    """The blocks an interleaved scheme holds out (0-based)."""
    return list(range(1, INTERLEAVED_BLOCKS, HELD_EVERY))


def block_index(series: ActuatorSeries, phase: float = 0.0) -> np.ndarray:
    """Each sample's block of an interleaved scheme: the run's time span in :data:`INTERLEAVED_BLOCKS` equal
    blocks, the grid shifted by ``phase`` of a block."""
    t = series.time_s
    span = max(float(t[-1] - t[0]), 1e-12)
    position = (t - t[0]) / span * INTERLEAVED_BLOCKS - phase
    return np.clip(np.floor(position), 0, INTERLEAVED_BLOCKS - 1).astype(int)


@dataclass(frozen=True)
class Segment:
    """One stretch of measured and simulated temperature: samples ``[lo, lo + n)`` of its run, held out as
    ``unit`` (a run, a block) when it is validation data."""

    time_s: np.ndarray
    measured_C: np.ndarray
    simulated_C: np.ndarray
    effort: np.ndarray
    run: str = ""
    lo: int = 0
    unit: str = ""
    signals: Signals | None = field(default=None, repr=False)  # its inputs (what excites an effect in it)


@dataclass(frozen=True)
class FitReport:
    """The outcome of fitting and validating one actuator.

    ``estimator`` is the fitted estimator whose model the report shows, and
    ``train_series`` the data it was fitted on (for cross-validation: every
    run), so that later steps (a diagnosis) need not fit again.
    """

    actuator: str
    method: str
    model: ThermalModel
    stderr: dict
    train: dict
    validation: dict
    train_segments: tuple[Segment, ...] = field(repr=False, default=())
    validation_segments: tuple[Segment, ...] = field(repr=False, default=())
    estimator: ThermalEstimator | None = field(repr=False, default=None)
    train_series: tuple[ActuatorSeries, ...] = field(repr=False, default=())
    flags: tuple[str, ...] = ()
    scheme: str = ""
    # terms of the requested model this log cannot identify: {"term", "reason"}
    set_aside: tuple[dict, ...] = ()
    units: str = "parts"  # what the held-out units are: "runs", "blocks" or "parts" (a run's tail)

    @property
    def train_residual_K(self) -> np.ndarray:
        """``measured - simulated`` over the training data, in the estimator's order."""
        return np.concatenate([s.measured_C - s.simulated_C for s in self.train_segments])

    @property
    def evidence(self) -> Evidence:
        """How much the validation holds (samples, span in time constants, distinct readings)."""
        return Evidence.of(self.validation_segments, self.model.params["RC_s"])

    @property
    def held(self) -> dict[str, float]:
        """Values held rather than fitted because the log cannot identify them (see ``set_aside``)."""
        return {a["parameter"]: a["held_at"] for a in self.set_aside if "parameter" in a}

    @property
    def channel_units(self) -> Mapping[str, str]:
        """The units of the log's effort, velocity, current and power channels (what parameter units are built
        on)."""
        return self.train_series[0].units if self.train_series else {}

    def unit(self, parameter) -> str:
        """A parameter's unit on this log (``K/(N m)^2``, ``K/mA^2``, or saying the channel's unit was not
        given)."""
        return parameter.unit_in(self.channel_units)

    def to_json(self) -> dict:
        """The record ``thermolimb fit --json`` prints."""
        units = {p.name: self.unit(p) for p in self.model.parameters}
        return {
            "actuator": self.actuator,
            "model": list(self.model.terms),
            "method": self.method,
            "channel_units": dict(self.channel_units),
            "params": {
                name: {"value": value, "stderr": float(self.stderr[name]), "unit": units[name]}
                for name, value in self.model.params.items()
            },
            "train": self.train,
            "validation": self.validation,
            "evidence": self.evidence.to_json(),
            "flags": list(self.flags),
            "flags_said": said_once(self.flags),  # as the text says them
            "set_aside": [dict(s) for s in self.set_aside],
            "validation_scheme": self.scheme,
        }


def _segments(model: ThermalModel, series: ActuatorSeries, pieces: Sequence[tuple[int, int]] | None = None,
              restart: bool = False, unit: str = "", offsets: Mapping[str, float] | None = None,
              runs: dict | None = None) -> list[Segment]:
    """Samples ``[lo, hi)`` of ``series`` for each piece (default: the whole run, or with a fit mask the
    pieces it is fitted on), all from one free run carried from the run's start (its hidden states started by
    ``offsets``), or restarted at ``lo - 1``.  ``runs`` keeps the free runs carried from a run's start: a free
    run is causal, so the training part of a split run is the start of the whole run's (a 1.4 M-sample run not
    simulated twice)."""
    if pieces is None:
        pieces = _runs_of(series.fit_mask) if series.fit_mask is not None else [(0, series.n)]
    # a run moved to the air of those fitted with it, shown as it read
    out, air = [], series.signals.air_shift_K
    if restart:
        for lo, hi in pieces:
            if lo > 0:
                part = series.slice(lo - 1, hi)
                # the trend at the restart comes from the data before it
                sim = model.free_run(part, series.slice(0, lo).rate_K_per_s(at_end=True))
                out.append(Segment(part.time_s, part.temperature_C + air, sim + air, part.signals.effort,
                                   series.run, lo - 1, unit or series.run, part.signals))
            else:
                out += _segments(model, series, [(lo, hi)], unit=unit)
        return out
    end = max(hi for _, hi in pieces)
    rate, runs = series.rate_K_per_s(), {} if runs is None else runs
    key = (id(model), rate, str(offsets), *(x.ctypes.data for x in (series.time_s, series.signals.effort,
                                                                     series.temperature_C)))
    if key not in runs or runs[key].size < end:
        runs[key] = model.free_run(series.slice(0, end), rate, offsets=offsets)
    sim = runs[key][:end]
    for lo, hi in pieces:
        label = unit or (series.run if len(pieces) == 1 else f"{series.run or 'run'} block {lo}-{hi}")
        out.append(Segment(series.time_s[lo:hi], series.temperature_C[lo:hi] + air, sim[lo:hi] + air,
                           series.signals.effort[lo:hi], series.run, lo, label, series.signals.slice(lo, hi)))
    return out


def burn_in(series: ActuatorSeries) -> int:
    """The samples of a held-out run that place its hidden states: its first :data:`BURN_IN_SHARE` of time."""
    t = series.time_s
    return max(1, int(np.searchsorted(t, t[0] + BURN_IN_SHARE * (t[-1] - t[0]), side="right")))


def _offsets(estimator, k: int) -> dict[str, float] | None:
    """Where the fit placed the hidden states of its ``k``-th run (an estimator that places them)."""
    offsets = getattr(estimator, "offsets_", None)
    return offsets[k] if offsets else None


def _runs_of(mask: np.ndarray) -> list[tuple[int, int]]:
    """``(lo, hi)`` of each stretch of consecutive ``True`` in ``mask``."""
    edges = np.flatnonzero(np.diff(np.r_[0, mask.astype(np.int8), 0]))
    return [(int(a), int(b)) for a, b in zip(edges[::2], edges[1::2])]


def _metrics(segments: Sequence[Segment]) -> dict:
    return pieces_metrics([(s.measured_C, s.simulated_C) for s in segments])


def make_estimator(method: str, model: str | Sequence[str]) -> ThermalEstimator:
    if method not in ESTIMATORS:
        raise LogError(f"unknown method {method!r}; expected one of {', '.join(ESTIMATORS)}")
    return ESTIMATORS[method](model=model)


# A fold: the series a model is fitted on, and for each series it is scored on, the pieces (lo, hi) of it.
Fold = tuple[list[ActuatorSeries], list[tuple[ActuatorSeries, list[tuple[int, int]]]]]


def scheme_folds(series: list[ActuatorSeries], scheme: Scheme) -> list[Fold]:
    if scheme.kind == HELD_OUT:
        return [(series, [(v, [(0, v.n)]) for v in scheme.held_out])]
    if scheme.kind == INTERLEAVED:
        fit_on, scored = [], []
        for s in series:
            block = block_index(s, scheme.phase)
            held = np.isin(block, held_blocks())
            if np.count_nonzero(held) < MIN_SAMPLES // 4 or np.count_nonzero(~held) < MIN_SAMPLES // 2:
                raise LogError(f"actuator {s.actuator}{s.run_label}: {s.n} "
                               "samples are too few to hold blocks out "
                               f"(at least {MIN_SAMPLES // 2} to fit and "
                               f"{MIN_SAMPLES // 4} to validate are needed); "
                               f"use a longer log, or several runs")
            fit_on.append(replace(s, fit_mask=~held))
            scored.append((s, _runs_of(held)))
        return [(fit_on, scored)]
    if scheme.kind == RUNS:
        if len(series) < 2:
            raise LogError(f"actuator {series[0].actuator}: --cv runs needs "
                           "at least two runs (several logs, or a log "
                           f"with pauses); this one has {len(series)}")
        return [([o for o in series if o is not s], [(s, [(0, s.n)])]) for s in series]
    if scheme.kind == PARTS:
        parts = []
        for s in series:
            edges = np.searchsorted(s.time_s, np.linspace(s.time_s[0], s.time_s[-1], scheme.parts + 1)[1:-1])
            edges = [0, *map(int, edges), s.n]
            if np.min(np.diff(edges)) < MIN_SAMPLES:
                raise LogError(f"actuator {s.actuator}{s.run_label}: {s.n} samples are too few to hold out "
                               f"{scheme.parts} parts of it (each needs at "
                               f"least {MIN_SAMPLES}); use a longer log, or "
                               f"several runs")
            parts += [replace(s.slice(lo, hi), run=f"{s.run + ' ' if s.run else ''}part {k + 1}")
                      for k, (lo, hi) in enumerate(zip(edges[:-1], edges[1:]))]
        return [([o for o in parts if o is not p], [(p, [(0, p.n)])]) for p in parts]
    if scheme.kind == BLOCKS:
        folds = []
        for s in series:
            edges = np.linspace(0, s.n, scheme.folds + 1).astype(int)
            if np.min(np.diff(edges)) < MIN_SAMPLES // 2:
                raise LogError(f"actuator {s.actuator}{s.run_label}: {s.n} "
                               f"samples are too few for {scheme.folds} "
                               f"folds (each needs at least {MIN_SAMPLES // 2}); "
                               "use fewer folds or a longer log")
            for lo, hi in zip(edges[:-1], edges[1:]):
                pieces = [p for p in (s.slice(0, lo), s.slice(hi, s.n)) if p.n >= MIN_SAMPLES // 2]
                folds.append((pieces + [o for o in series if o is not s], [(s, [(int(lo), int(hi))])]))
        return folds
    cuts = [s.split_index(scheme.split) for s in series]
    return [([s.slice(0, c) for s, c in zip(series, cuts)], [(s, [(c, s.n)]) for s, c in zip(series, cuts)])]


def validate_model(
    series: Sequence[ActuatorSeries],
    model: str | Sequence[str],
    scheme: Scheme = Scheme(),
    make: Callable[[], ThermalEstimator] | None = None,
    method: str = "output_error",
    reduce: bool = False,
    fixed: Mapping[str, float] | None = None,
    datasheet: Mapping[str, float] | None = None,
) -> FitReport:
    """Fit and validate one actuator (one or several runs) by ``scheme``; ``make()`` gives a fresh estimator.

    With ``reduce``, a term the log cannot identify is set aside and the largest sub-model the log identifies
    is fitted (:func:`identifiable_submodel`; said in the report's ``set_aside``); without it, the
    :class:`~thermolimb.identification.IdentifiabilityError` is raised.  ``fixed``: values held, not fitted
    (output error only); ``datasheet``: values held only where the log cannot identify them (with ``reduce``).
    """
    if reduce:
        if make is not None:
            raise ValueError("validate_model(reduce=True) builds its own estimators; give method, not make")

        def fit(terms, held):
            return validate_model(series, terms, scheme, None, method, fixed=held)

        return identifiable_submodel(fit, parse_model(model), series, hold=method == "output_error",
                                     datasheet=datasheet)
    series, air_C = common_air(list(series))  # runs in different air: each its own offset (Eq. 5)
    scheme = scheme.resolved(series)
    if make is None and fixed:
        make = lambda: ESTIMATORS["output_error"](model=model, fixed=fixed)  # noqa: E731
    make = make or (lambda: make_estimator(method, model))
    folds = scheme_folds(series, scheme)
    restart = scheme.restart and scheme.kind in (SPLIT, BLOCKS)
    fitted = [make().fit(fit_on) for fit_on, _ in folds]
    # a held-out unit is a whole run (named, or numbered in its order), else a block or a run's tail
    number = {id(s): k for k, s in enumerate(scheme.held_out if scheme.kind == HELD_OUT else series)}
    whole_runs = scheme.kind in (RUNS, PARTS, HELD_OUT)
    valid, moved, alive = [], [], []
    runs: dict = {}  # free runs from each run's start, by model, run and start (_segments)
    for est, (fit_on, scored) in zip(fitted, folds):
        # another run may have run in another air; parts of one run share its air, whose swings are its own
        # evidence
        span = ambient_span(fit_on) if scheme.kind in (RUNS, HELD_OUT) else None
        for k, (s, pieces) in enumerate(scored):
            judged = est.model_
            if whole_runs:  # the run's hidden states placed by its first tenth, which is not scored
                burn = burn_in(s)
                label = s.run or f"run {number[id(s)] + 1}"
                shift = ambient_shift_K(judged, span, s.signals.ambient_C)  # another run, maybe another air
                if shift:
                    judged = shifted(judged, shift)
                    moved.append((label, shift))
                offsets = judged.place_hidden(s, np.arange(burn))[1]
                pieces = [(burn, s.n)]
            # the same run fitted on: its hidden states as the fit placed them (not for contiguous folds)
            else:
                offsets = _offsets(est, k) if scheme.kind in (SPLIT, INTERLEAVED) else None
                label = ""
            valid += _segments(judged, s, pieces, restart, label, offsets, runs)
            alive.append(judged)  # while its id keys the free runs
    valid = tuple(valid)
    if len(folds) == 1:
        final, train_series = fitted[0], folds[0][0]
    else:
        final, train_series = make().fit(series), series
    train = tuple(
        seg
        for k, s in enumerate(train_series)
        for seg in _segments(final.model_, s, offsets=_offsets(final, k), runs=runs)
    )
    held = list(getattr(final, "fixed", None) or [])
    train_metrics = _metrics(train)
    carry = []
    if scheme.kind == HELD_OUT:  # a run it was not fitted on: does the model carry to it, and if not, why
        carry = carry_flags(valid, train_series, scheme.held_out, train_metrics["rmse_K"])
    return FitReport(
        actuator=series[0].actuator, method=final.method, model=final.model_, stderr=final.stderr_,
        train=train_metrics, validation=_metrics(valid), train_segments=train, validation_segments=valid,
        estimator=final, train_series=tuple(train_series),
        flags=tuple(parameter_flags(final.model_, final.stderr_, series, held=held,
                                    train_rmse_K=train_metrics["rmse_K"],
                                    covariance=getattr(final, "covariance_", None))) + tuple(carry),
        scheme=scheme.describe() + air_words(series, air_C) + moved_words(moved),
        units="runs" if scheme.kind in (RUNS, HELD_OUT) else "parts" if scheme.kind == PARTS else "blocks")


def fit_and_validate(
    series: Sequence[ActuatorSeries],
    model: str | Sequence[str],
    split: float = 0.7,
    method: str = "output_error",
    estimator: ThermalEstimator | None = None,
    restart_at_split: bool = False,
) -> FitReport:
    """Fit jointly on the first ``split`` of every series (one actuator, one or several runs), validate on the
    rest."""
    make = (lambda: estimator) if estimator is not None else None
    return validate_model(series, model, Scheme.at_split(split, restart_at_split), make=make, method=method)
