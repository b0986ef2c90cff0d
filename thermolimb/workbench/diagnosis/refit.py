"""Refitting a candidate change so that where it ends does not depend on where it starts.

A candidate's refit is a nonlinear least-squares fit of the free run; most of
its parameters enter the simulated temperature almost linearly (heat sizes,
offsets), and a few do not: a mass's or a sensor's time constant, a gain on a
conductance (airflow, a fan's duty, the neighbours' conduction, copper's
temperature coefficient).  A local fit started wherever a quick screen ranked
first can end in a different basin when the log changes in its last digits
(a few rows trimmed), which is what made verdicts on real logs flip.

So the refit searches that one nonlinear parameter globally and
deterministically, then refines:

1. **Profile.**  The candidate's most nonlinear parameter (:func:`profiled_parameter`:
   a time constant first, else a parameter that changes the conductance) is
   held at each of :data:`PROFILE_POINTS` log-spaced values the log can show
   (:func:`profile_grid`), and the other parameters are fitted briefly from the
   score test's best start.  A profile is a one-dimensional global search: it
   looks at every basin along the parameter instead of the one a start falls in,
   at the cost of a few short fits (argued against trying every start fully,
   which costs two to three diagnoses, and a reparameterisation, which would
   have to be found term by term and for users' terms too).
2. **Refine.**  Every parameter is fitted from the best profile point; a
   second point whose short fit came within :data:`COMPETING` of the best is
   refined too, and the refit with the lower training error is kept (two
   basins of nearly equal error are both looked at to the end).
3. **Fallback.**  If a refit cannot identify a parameter, or the effect
   collapses to its null or a time constant runs to a bound, the next profile
   point is refined, up to :data:`MAX_REFINES` refits, before the candidate is
   said to fail.

A term with no nonlinear parameter is refitted from its starts, the best
screened first, with the same fallback.
"""

from __future__ import annotations

from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import replace

import numpy as np

from ...identification import FreeRunLeastSquares, IdentifiabilityError
from ...model.model import hidden_states, model_parameters
from ...model.terms import TERMS, Parameter
from ...util.errors import TermError
from ...util.parallel import Runner, one_blas_thread, shared
from ...util.progress import progress
from ..floor import SensorFloor
from ..validation import FitReport, validate_model
from .bringing import brought_start, not_brought
from .candidates import SCAN_POINTS, SCORE_P_VALUE, Candidate, scan_values
from .judgement import judge, refit_failure

ALWAYS_REFIT = 3  # the best-scoring additions are refitted even when the score test is weak
PROFILE_POINTS = SCAN_POINTS  # values of the profiled parameter, log-spaced
PROFILE_EVALUATIONS = 4  # trust-region iterations of each profile point's short fit
# a second profile point is refined too when its short fit's error is within this of the best's
COMPETING = 1.25
MAX_REFINES = 2  # refits in full at most: a refit that fails or collapses passes to the next point
SCREEN_EVALUATIONS = 2  # of each start's short fit, for a term with nothing to profile
# the short fits rank starting points only: on a long log they compare at most this many samples (the 6 M-row
# Parquet's knee: 20 times fewer blocks than a fit's 100,000, the same starts chosen; see
# docs/measurements.md)
SCREEN_SAMPLES = 20_000
GAIN_RANGE = (0.03, 30.0)  # a gain is profiled over these multiples of its typical size
REFIT_EVALUATIONS = 12  # simulations per parameter for a refit; good fits need fewer than 10
# a diagnosis's refits go to local workers when one of them places a hidden state (a slow mass, a lagging
# sensor: one more free run per state and evaluation; UR3 J5's second mass 1-2 s, the others 0.1-0.3 s;
# without one the README tour's refits take 0.02-0.08 s, less than the pool's start) and the log is at most
# this long (samples over its runs): each refit comes back with its report, which on a long log costs more to
# send than it saves
POOLED_SAMPLES = 200_000


def profiled_parameter(term, params: dict, series) -> Parameter | None:
    """The term's parameter to search globally: a time constant (unit s; the nuisance one first), else the
    first parameter that changes the conductance to ambient (the ``gain`` a term's contribution returns moves
    with it), else ``None``."""
    times = sorted((p for p in term.parameters if p.unit == "s"), key=lambda p: not p.nuisance)
    if times:
        return times[0]
    signals = series.signals
    base = {**params, **{p.name: p.typical for p in term.parameters}}
    try:
        _, gain = term().contribution(base, signals)
    except (KeyError, TypeError, ValueError, ArithmeticError):  # a term that needs more than the base has
        return None
    for p in term.parameters:
        moved = {**base, p.name: 2.0 * p.typical if p.typical else 1.0}
        try:
            _, other = term().contribution(moved, signals)
        except (KeyError, TypeError, ValueError, ArithmeticError):
            continue
        if np.any(np.asarray(other) != np.asarray(gain)):
            return p
    return None


def profile_grid(param: Parameter, train) -> np.ndarray:
    """The values a profile holds ``param`` at: the time scales the score scans for a time
    (:func:`~.candidates.scan_values`), multiples of the typical size for a gain; within the parameter's
    bounds, never at its null."""
    if param.unit == "s":
        values = scan_values(param, train)
    else:
        size = abs(param.typical) or 1.0
        values = np.sign(param.typical or 1.0) * size * np.geomspace(*GAIN_RANGE, PROFILE_POINTS)
    span = param.upper - param.lower if np.isfinite(param.upper - param.lower) else np.abs(values).max()
    values = np.clip(values, param.lower + 1e-6 * span, param.upper - 1e-6 * span)
    return np.unique(values[values != param.null])


def ordered_starts(
    cand: Candidate, base, train, param: Parameter | None | bool = True
) -> list[tuple[float, dict]]:
    """Where the full refit may start, best first, each with its short fit's training cost (``inf`` when not
    screened): the profile's points, or for a term with nothing to profile, its starts screened the same way.
    ``param``: the profiled parameter when the caller has it (``True``: find it here)."""
    keep = {p.name for p in model_parameters(cand.model)}
    starts = [{k: v for k, v in start.items() if k in keep} for start in cand.starts or [{}]]
    held = dict(base.held or {})
    term = cand.searched if cand.adds else None
    if param is True:
        param = profiled_parameter(term, dict(base.model.params), train[0]) if term is not None else None
    if param is not None and param.name not in held:
        # each point starts where the score's linearised step put the other parameters for that value, if it
        # scanned it (a nuisance time), else from the best start
        scanned = {round(f[param.name], 9): start for f, start in cand.scan if param.name in f}
        # a size at its null leaves the profiled parameter without effect (a mass of no share has no time
        # constant): such a start takes the size's typical value instead
        absent = {p.name: p.typical for p in term.parameters if p is not param and not p.nuisance}
        points = []
        for value in profile_grid(param, train):
            start = scanned.get(round(float(value), 9), starts[0])
            start = {k: v for k, v in start.items() if k in keep}
            start.update({k: v for k, v in absent.items()
                          if abs(start.get(k, v) - _null(term, k)) <= 1e-9 * max(abs(v), 1e-12)})
            points.append(({**start, param.name: float(value)}, {**held, param.name: float(value)}))
        evaluations = PROFILE_EVALUATIONS
    elif len(starts) > 1:
        points = [(start, held) for start in starts]
        evaluations = SCREEN_EVALUATIONS
    else:
        return [(np.inf, start) for start in starts]
    screened = []
    for initial, fixed in points:
        try:
            est = FreeRunLeastSquares(model=cand.model, initial=initial, max_iterations=evaluations,
                                      fixed=fixed or None, max_samples=SCREEN_SAMPLES)
            est.fit(train)
        except IdentifiabilityError:
            continue
        screened.append((float(est.optimizer_result_.cost), len(screened), dict(est.params_)))
    return [(cost, params) for cost, _, params in sorted(screened, key=lambda x: x[:2])] or \
        [(np.inf, start) for start in starts]


def _null(term, name: str) -> float:
    return next(p.null for p in term.parameters if p.name == name)


def refit(cand: Candidate, base, base_bic: float, evaluate, warm: dict | None = None) -> Candidate:
    """``cand`` refitted (profile, refine, fall back; module docstring) and judged on held-out data.

    ``evaluate(model, initial, fixed)`` fits and validates a model the way the diagnosis does.  ``warm``:
    where the same change ended on the unperturbed log (a stability replicate's start, :mod:`.stability`);
    refined from there, and searched as above only if that refit fails or finds no such effect, or (``cand``'s
    ``settled_plausible``) lands implausible where the whole log's refit was plausible.
    """
    term = TERMS[cand.effect] if cand.adds else None
    param = (
        profiled_parameter(cand.searched, dict(base.model.params), base.train_series[0])
        if cand.adds
        else None
    )
    keep = {p.name for p in model_parameters(cand.model)}
    errors, collapsed, found = [], None, []

    def attempt(start: dict, searched: bool = True) -> bool:
        """Refine from ``start``; keep the report if it found the effect (a collapse is kept, to report, only
        from the search's own starts). Whether it did."""
        nonlocal collapsed
        try:
            report = replace(evaluate(cand.model, {k: v for k, v in start.items() if k in keep}, base.held),
                             set_aside=base.set_aside)
        except IdentifiabilityError as exc:
            if searched:
                errors.append(str(exc))
            return False
        if term is not None and refit_failure(term, report.model.params) is not None:
            if searched:
                # the first refit that found no such effect, if none does better
                collapsed = collapsed or report
            return False
        found.append(report)
        return True

    # from where the whole log's refit ended, when given (a replicate): that refit is the replicate's, and the
    # profile searches afresh only if it fails or collapses.  The whole log's search has chosen the basin; a
    # replicate asks whether a perturbed log keeps the change there, from a jittered start (searching every
    # replicate afresh cost two thirds of the stability check on the UR3's J5 and took the same changes)
    if warm is not None and attempt(warm, searched=False):
        if not (cand.settled_plausible and term is not None and term().implausible(found[0].model.params)):
            return judge(cand, found[0], base, base_bic)
        # the whole log's refit was plausible and this one is not: a jittered start rolled along a valley into
        # another basin (a slow mass's share and time constant trade on a log that shows only the start of its
        # rise), which the search below looks past, as it did for the whole log
        found.clear()
    if cand.kind == "add" and cand.brings:  # two masses at once, a pair: one refit from where one ended
        return replace(cand, failure=f"refitted from where {cand.brings[0]} alone ended, no {cand.effect} "
                                     "was found with it")
    starts = ordered_starts(cand, base, list(base.train_series), param)
    profiled = 0
    for cost, start in starts[:MAX_REFINES]:
        if profiled and not cost <= COMPETING * starts[0][0]:
            break  # a refit found the effect, and no other basin competes with it
        profiled += attempt(start)
    if found:  # the refined basins' best by training error (held-out data judges the change, not the start),
        # a physically plausible one first (a second mass that came out faster than the winding is the two
        # masses' roles swapped: another basin, not another effect)
        best = min(found, key=lambda r: (term is not None and term().implausible(r.model.params) is not None,
                                         float(r.train_residual_K @ r.train_residual_K)))
        return judge(cand, best, base, base_bic)
    if collapsed is not None:
        return judge(cand, collapsed, base, base_bic)
    return replace(cand, identifiable=False, failure=f"not identifiable from this log: {errors[0]}")


def refits(candidates: list[Candidate], base, series, scheme, refit: str = "strong", workers: int = 1,
           quiet: bool = True, floor: SensorFloor | None = None) -> list[Candidate]:
    """The refit stage: the screened ``candidates`` with the refits' records, in the same order.

    Parameters
    ----------
    candidates, base
        The screen's records (:func:`.screen.screened`) and the base stage's (:class:`.screen.Base`).
    series, scheme
        The log and how held-out error is measured (:class:`~thermolimb.workbench.validation.Scheme`).
    refit
        ``"strong"``: the changes worth a refit (:func:`worth_refitting`), then a change that brings terms
        with it where a simpler one calls for it (:mod:`.bringing`); ``"all"``: every judgeable change.
    workers, quiet
        Local processes for the refits (:func:`refit_all`); no progress bar when quiet.
    floor
        The sensor's floor where the base model has reached it: then nothing is refitted, and the changes
        worth a refit say why.
    """
    worth, passed = worth_refitting([c for c in candidates if c.broken is None], refit)
    done = dict(passed)
    if floor is not None:  # nothing can be told apart: nothing is refitted
        why = f"the model is already at the sensor's floor ({floor.sentence(base.rmse_K)})"
        done.update((c.label, replace(c, skipped=why)) for c in worth)
        return [done.get(c.label, c) for c in candidates]
    bringing, worth = [c for c in worth if c.brings], [c for c in worth if not c.brings]
    worth = refit_all(worth, [None] * len(worth), series, scheme, base.report, base.bic, workers, quiet)
    done.update((c.label, c) for c in worth)
    for cand in bringing:
        skipped = not_brought(cand, worth)
        done[cand.label] = replace(cand, skipped=skipped) if skipped is not None else refit_candidate(
            cand, series, scheme, base.report, base.bic, brought_start(cand, worth))
    return [done.get(c.label, c) for c in candidates]


def worth_refitting(candidates: list[Candidate], refit: str) -> tuple[list[Candidate], dict[str, Candidate]]:
    """Every drop and swap; additions whose score test is significant and the few that explain most of the
    residual (catalog effects and channels counted apart); of a channel's forms, only the strongest on each
    place it can act (the winding, each slow mass: the score test is local, and ranked a fan's form on a fast
    mass above the slow mass's that is the physics; docs/workbench.md); the others say so.  ``(the changes
    worth a refit, {label: record} of the forms passed over, each saying why})``."""
    adds = [c for c in candidates if c.adds and c.confounded is None and c.unexcited is None]
    strongest: dict[tuple, Candidate] = {}
    for c in adds:
        key = _place(c)
        if c.kind == "channel" and (key not in strongest or c.score > strongest[key].score):
            strongest[key] = c
    groups = ([c for c in adds if c.kind == "add" and not c.brings], list(strongest.values()))
    top = {id(c) for group in groups for c in sorted(group, key=lambda c: -c.partial_r2)[:ALWAYS_REFIT]}
    chosen, passed = [], {}
    for c in candidates:
        if c.confounded is not None or c.unexcited is not None:
            continue
        if refit == "all" or not c.adds:
            chosen.append(c)
        elif c.kind == "channel" and c is not strongest[_place(c)]:
            why = (f"{strongest[_place(c)].effect} explains more of the residual with the same channel "
                   f"{c.channel}")
            passed[c.label] = replace(c, skipped=why,
                                      evidence=f"score test p = {c.p_value:.2g}; not refitted: {why}.")
        elif c.p_value < SCORE_P_VALUE or id(c) in top or (c.kind == "add" and (c.brings or _moves_heat(c))):
            chosen.append(c)  # two masses at once: bringing.py
    return chosen, passed


def _moves_heat(c: Candidate) -> bool:
    """An addition that moves a heat the model has on the winding into a slow mass (friction in the housing):
    refitted whatever its local score, which the winding's own term for that heat nearly spans (p = 0.55 where
    the refit cut the held-out error from 0.931 to 0.335 K on the forecast benchmark's calibration log:
    docs/workbench.md)."""
    return TERMS[c.effect].heats_slow_mass


def _place(c: Candidate) -> tuple:  # a channel form's channel, the slow mass it acts on (None: the winding)
    return c.channel, TERMS[c.effect].airflow_on


_COMPARED = ContextVar("compared", default=None)  # samples a fit compares at most (None: thinning's own)


@contextmanager
def compared_on(samples: int):
    """Fits made by :func:`evaluate` within compare at most ``samples`` samples of what they fit on (a
    stability replicate's, :mod:`.stability`); validation stays at the full rate."""
    token = _COMPARED.set(samples)
    try:
        yield
    finally:
        _COMPARED.reset(token)


def evaluate(series, model, scheme, initial=None, fixed=None) -> FitReport:
    """Fit and validate ``model`` on ``series`` by ``scheme`` the way the diagnosis does, from ``initial``
    with the parameters in ``fixed`` held."""
    def make():
        return FreeRunLeastSquares(model=model, initial=initial or None, max_nfev=REFIT_EVALUATIONS,
                                   fixed=fixed or None, max_samples=_COMPARED.get())

    return validate_model(series, model, scheme, make=make)


def set_aside(cand: Candidate, exc: TermError) -> Candidate:
    """``cand`` set aside: a user's term broke its contract while it was tried
    (:class:`~thermolimb.model.guard.TermError`); the record says why, and the diagnosis goes on."""
    return replace(cand, broken=str(exc), rmse_K=None, evidence=f"set aside: {exc}")


def refit_candidate(cand: Candidate, series, scheme, base: FitReport, base_bic: float,
                    warm: dict | None = None) -> Candidate:
    """``cand`` refitted by :func:`refit` (a deterministic profile over its nonlinear parameter, then the next
    start while a refit fails; from ``warm`` first, if given) and judged on held-out data; set aside
    (:func:`set_aside`) where a user's term breaks its contract in the refit."""
    def fitted(model, initial, fixed):
        return evaluate(series, model, scheme, initial, fixed)

    try:
        return refit(cand, base, base_bic, fitted, warm)
    except TermError as exc:
        return set_aside(cand, exc)


def refit_all(
    cands: list[Candidate],
    warm: list,
    series,
    scheme,
    base: FitReport,
    base_bic: float,
    workers: int,
    quiet: bool = True,
) -> list[Candidate]:
    """Every candidate in ``cands`` refitted (``warm``: each one's start, or ``None``), guarded, in the same
    order, on ``workers`` local processes when more than one, one places a hidden state and the log is short
    (:data:`POOLED_SAMPLES`), else here.  Each refit is independent of the others and runs with one BLAS
    thread wherever it runs, so the candidates end the same, bit for bit, either way; pooled, the
    longest-looking (most parameters) go first."""
    pooled = (workers > 1 and len(cands) > 1 and any(hidden_states(c.model) for c in cands)
              and sum(s.n for s in series) <= POOLED_SAMPLES)
    bar = progress(total=len(cands), desc="refits", disable=quiet)
    order = sorted(range(len(cands)), key=lambda i: -len(model_parameters(cands[i].model)))
    out = list(cands)
    with Runner(
        "process" if pooled else "serial", workers, shared=(series, scheme, base, base_bic)
    ) as runner:
        for i, done in runner.as_completed(_refit_job, [(cands[i], warm[i]) for i in order]):
            out[order[i]] = done
            bar.update()
    bar.close()
    return out


def _refit_job(cand: Candidate, warm: dict | None) -> Candidate:
    """One candidate's refit, on the log the runner shares."""
    with one_blas_thread():
        return refit_candidate(cand, *shared(), warm)
