"""Forms the catalog lacks: a sparse regression on the heat balance, over a library of physical features.

When no change of the catalog or of the log's channels helps and the
residual still has structure, :func:`propose` asks which few features of the
logged signals explain it.  The library holds forms a heat balance allows:
powers of |velocity| and of |effort|, heat above a speed threshold
(``max(0, |v| - v0)^2``), heat growing with temperature (``effort^2 (T - 25)``,
copper), cooling growing with speed, the pull of every other logged
temperature (``T_x - T``), and the extra channels' heat and conductance forms.

The regression is on the free run's residual, not on a differentiated
temperature: each feature ``f`` enters as its *signature*, the change of the
simulated temperature when the model gains the heat ``c f`` (computed by the
model itself, so a lag, a slow mass or a lagging sensor shapes it exactly as
it would the real effect), with the part the fitted parameters can already
produce projected out, as in the score test of :mod:`.candidates`.  A
signature the model already has is confounded and left out of the library.

Orthogonal matching pursuit picks the features (scikit-learn's
``orthogonal_mp``: a maintained, exact greedy solver; the library's
features are strongly correlated powers of one speed, where OMP's one pick
per family reads better than a Lasso path that spreads weight over
neighbouring exponents, and OMP needs no penalty to tune).  A feature is kept
while it explains at least :data:`MIN_SHARE` of what is left, at most
:data:`MAX_FEATURES` of them.  The proposal is a generated term
(:mod:`thermolimb.model.generated`) with one coefficient per feature; its
exponents and thresholds are fixed at the library's values.  It is refitted
in the full model by output error and validated on held-out data like any
candidate, and labelled a discovered form, not a known effect.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ...identification.thinning import fit_rows
from ...logs import ActuatorSeries
from ...model.generated import Feature, Spec, define, identifier
from ...model.model import ThermalModel
from ...model.terms import TERMS, Parameter, Term, register_term, unregister_term
from .candidates import Candidate, score_candidate
from .channels import in_temperature_range, is_temperature, unused_channels
from .explain import describe_discovered
from .refit import refit_candidate
from .screen import rank

MAX_FEATURES = 2
SPEED_POWERS = (1.5, 2.5, 3.0, 4.0)  # |v| and v^2 are the catalog's speed losses
# thresholds of heat above a speed, as quantiles of the speed while moving
SPEED_QUANTILES = (0.25, 0.5, 0.75)
EFFORT_POWERS = (1.0, 3.0)  # |F|; F^2 is the Joule heat itself
# a feature is kept while it explains at least this share of what is left of the residual.  No significance
# test here: a thermal residual's serial correlation leaves a two-hour log a few dozen independent samples,
# and a test on them would refuse forms that halve the held-out error.  The regression proposes; held-out data
# decide.
MIN_SHARE = 0.01
OWN_SHARE = 1e-3  # a feature whose signature is less than this share its own is confounded with the model
PROBE = "_discovery_probe"


@dataclass(frozen=True)
class LibraryFeature:
    """A feature and the log columns it reads."""

    key: str
    feature: Feature
    columns: tuple[str, ...]


@dataclass
class Proposal:
    """A discovered form: its generated term's name, formula, and how the regression chose it."""

    term: str
    formula: str
    words: str
    coefficients: list[float]
    partial_r2: float
    library_size: int
    source: str


def _speed_features(speed: np.ndarray) -> list[LibraryFeature]:
    out = []
    for n in SPEED_POWERS:
        out.append(
            LibraryFeature(
                f"speed_p{n:g}".replace(".", "_"),
                Feature(
                    "",
                    f"K/({{velocity}})^{n:g}",
                    "velocity",
                    "abs_power",
                    f"|v|^{n:g}",
                    f"|velocity| to the power {n:g}",
                    power=n,
                ),
                ("velocity",),
            )
        )
    moving = speed[speed > 0.01 * speed.max()] if speed.max() > 0 else speed
    for q in SPEED_QUANTILES:
        v0 = float(f"{np.quantile(moving, q):.2g}")
        if v0 <= 0:
            continue
        out.append(LibraryFeature(f"speed_over_{v0:g}".replace(".", "_"), Feature(
            "", "K/({velocity})^2", "velocity", "above", f"max(0, |v| - {v0:g})^2",
            f"the square of |velocity| above {v0:g}", threshold=v0), ("velocity",)))
    out.append(
        LibraryFeature(
            "speed_cooling",
            Feature(
                "",
                "1/({velocity})",
                "velocity",
                "abs_power",
                "|v| (T - T_offset)",
                "|velocity| times the rise above the offset",
                gain=True,
            ),
            ("velocity",),
        )
    )
    return out


def _effort_features(effort: np.ndarray) -> list[LibraryFeature]:
    out = [
        LibraryFeature(
            f"effort_p{n:g}",
            Feature(
                "",
                f"K/({{effort}})^{n:g}" if n != 1 else "K/({effort})",
                "effort",
                "abs_power",
                f"|F|^{n:g}" if n != 1 else "|F|",
                f"|effort| to the power {n:g}",
                power=n,
            ),
            ("effort",),
        )
        for n in EFFORT_POWERS
    ]
    f0 = float(f"{np.quantile(np.abs(effort), 0.75):.2g}")
    if f0 > 0:
        out.append(
            LibraryFeature(
                f"effort_over_{f0:g}".replace(".", "_"),
                Feature(
                    "",
                    "K/({effort})^2",
                    "effort",
                    "above",
                    f"max(0, |F| - {f0:g})^2",
                    f"the square of |effort| above {f0:g}",
                    threshold=f0,
                ),
                ("effort",),
            )
        )
    out.append(
        LibraryFeature(
            "effort2_temperature",
            Feature(
                "",
                "1/({effort})^2",
                "effort",
                "square",
                "F^2 (T - 25 degC)",
                "effort squared times the temperature above 25 degC",
                gain=True,
                reference="25.0",
            ),
            ("effort",),
        )
    )
    return out


def _pull(key: str, reference: str, symbol: str, words: str, columns=()) -> LibraryFeature:
    """``c (T_x - T)``: the pull of another temperature (a gain of ``-c`` with the reference ``T_x``)."""
    return LibraryFeature(
        key,
        Feature("", "1", "effort", "one", symbol, words, gain=True, reference=reference, sign=-1.0),
        columns,
    )


def library(model: tuple[str, ...], series: list[ActuatorSeries]) -> list[LibraryFeature]:
    """The features this log can feed, for a model ``model`` (its extra channels' forms included)."""
    s = series[0].signals
    out = _effort_features(np.concatenate([x.signals.effort for x in series]))
    if s.velocity is not None:
        out += _speed_features(np.abs(np.concatenate([x.signals.velocity for x in series])))
    if s.current_A is not None:
        out.append(LibraryFeature("current_p2", Feature("", "K/({current})^2", "current", "square", "I^2",
                                                        "current squared"), ("current",)))
        out.append(
            LibraryFeature(
                "current2_temperature",
                Feature(
                    "",
                    "1/({current})^2",
                    "current",
                    "square",
                    "I^2 (T - 25 degC)",
                    "current squared times the temperature above 25 degC",
                    gain=True,
                    reference="25.0",
                ),
                ("current",),
            )
        )
    for column, words in (("ambient", "the logged ambient"), ("housing", "the housing temperature"),
                          ("neighbors", "the neighbours' mean temperature")):
        if s.has(column):
            out.append(
                _pull(f"{column}_pull", column, f"({column} - T)", f"the pull of {words}", columns=(column,))
            )
    for channel in unused_channels(model, series):
        unit, column = series[0].units.get(f"extra.{channel}"), f"extra.{channel}"
        key = identifier(channel)
        values = np.concatenate([x.signals.extra[channel] for x in series])
        named = is_temperature(channel, unit)
        if named or in_temperature_range(values, unit, series):
            out.append(
                _pull(f"{key}_pull", column, f"({channel} - T)", f"the pull of `{channel}`", (column,))
            )
        if named:
            continue
        template = f"{{extra.{channel}}}"
        out += [
            LibraryFeature(
                f"{key}_heat",
                Feature("", f"K/({template})", column, "value", channel, f"`{channel}`"),
                (column,),
            ),
            LibraryFeature(
                f"{key}_sq",
                Feature("", f"K/({template})^2", column, "square", f"{channel}^2", f"`{channel}` squared"),
                (column,),
            ),
            LibraryFeature(
                f"{key}_effort",
                Feature(
                    "",
                    f"K/({template} · {{effort}})",
                    column,
                    "times_abs_effort",
                    f"{channel} |F|",
                    f"`{channel}` times |effort|",
                ),
                (column, "effort"),
            ),
            LibraryFeature(
                f"{key}_cooling",
                Feature(
                    "",
                    f"1/({template})",
                    column,
                    "value",
                    f"{channel} (T - T_offset)",
                    f"`{channel}` times the rise above the offset",
                    gain=True,
                ),
                (column,),
            ),
        ]
    return out


def feature_values(
    feature: Feature, series: ActuatorSeries, offset_C: float
) -> tuple[np.ndarray, np.ndarray | None]:
    """The feature's values on a series, and its reference temperature (degC) for a gain feature."""
    values = feature.values(series.signals).copy()
    return values, (feature.reference_values(series.signals, offset_C).copy() if feature.gain else None)


class _Probe(Term):
    """The heat ``c f`` of one library feature (``f`` and, for a gain feature, its reference, passed as extra
    channels): registered only while the signatures are computed."""

    name = PROBE
    description = "a library feature under test"
    parameters = (Parameter("_discovery_probe_coef", "1", -np.inf, np.inf, 1.0, "probe"),)
    columns = ("extra._f",)
    generated = True

    def contribution(self, p, s):
        k = p["_discovery_probe_coef"] * s.extra["_f"]
        if "_ref" in s.extra:
            return -k * s.extra["_ref"], k
        return k, 0.0


def signatures(base: ThermalModel, train: list[ActuatorSeries], features: list[LibraryFeature],
               stride: int = 1) -> np.ndarray:
    """Each feature's signature in the free run per unit coefficient (columns), over every ``stride``-th
    sample of the training series."""
    register_term(_Probe)
    try:
        model = ThermalModel(base.terms + (PROBE,), {**base.params, "_discovery_probe_coef": 0.0})
        columns = []
        for lf in features:
            runs = []
            for s in train:
                f, ref = feature_values(lf.feature, s, base.params["T_offset_C"])
                extra = {**s.signals.extra, "_f": f * lf.feature.sign}
                if ref is not None:
                    extra["_ref"] = ref
                probe = replace(s, signals=replace(s.signals, extra=extra))
                size = np.max(np.abs(f)) or 1.0
                step = (1e-3 if ref is not None else 0.1) / size
                at_null = model.free_run(probe)
                moved = model.with_params({**model.params, "_discovery_probe_coef": step}).free_run(probe)
                rows = fit_rows(s, stride)
                runs.append((moved[rows] - at_null[rows]) / step)
            columns.append(np.concatenate(runs))
        return (
            np.column_stack(columns)
            if columns
            else np.empty((sum(fit_rows(s, stride).size for s in train), 0))
        )
    finally:
        unregister_term(PROBE)


def propose(base: ThermalModel, train: list[ActuatorSeries], jacobian: np.ndarray, residual: np.ndarray,
            name_prefix: str = "discovered", stride: int = 1) -> Proposal | None:
    """The few library features that explain the residual significantly, as a generated term, or ``None``."""
    from sklearn.linear_model import (
        orthogonal_mp,  # scikit-learn takes ~0.1 s to import: only when discovering
    )

    features = [lf for lf in library(base.terms, train)
                if np.ptp(np.concatenate([feature_values(lf.feature, s, 0.0)[0] for s in train])) > 0]
    if not features or not residual @ residual > 0:
        return None
    S = signatures(base, train, features, stride)
    coef, *_ = np.linalg.lstsq(jacobian, S, rcond=None)
    S_perp = S - jacobian @ coef
    size, own = np.linalg.norm(S, axis=0), np.linalg.norm(S_perp, axis=0)
    usable = np.flatnonzero((size > 0) & (own > OWN_SHARE * np.maximum(size, 1e-300)))
    if usable.size == 0:
        return None
    X = S_perp[:, usable] / own[usable]
    path = np.atleast_2d(orthogonal_mp(X, residual, n_nonzero_coefs=min(MAX_FEATURES, usable.size),
                                       return_path=True).T)
    order: list[int] = []
    for step in path:
        order += [int(k) for k in np.flatnonzero(step) if int(k) not in order]
    chosen, r2_before = [], 0.0
    total = float(residual @ residual)
    for k in order:
        trial = chosen + [k]
        beta, *_ = np.linalg.lstsq(X[:, trial], residual, rcond=None)
        left = residual - X[:, trial] @ beta
        r2 = 1.0 - float(left @ left) / total
        if (r2 - r2_before) / max(1.0 - r2_before, 1e-12) < MIN_SHARE:
            break
        chosen, r2_before = trial, r2
    if not chosen:
        return None
    picked = [features[usable[k]] for k in chosen]
    beta, *_ = np.linalg.lstsq(S_perp[:, usable[chosen]], residual, rcond=None)
    return _proposal(picked, [float(b) for b in beta], r2_before, len(features), train, name_prefix)


def _proposal(
    picked: list[LibraryFeature], beta: list[float], r2: float, size: int, train, prefix: str
) -> Proposal:
    name = f"{prefix}_" + "_".join(lf.key for lf in picked)
    features, columns = [], []
    for k, (lf, b) in enumerate(zip(picked, beta), start=1):
        features.append(replace(lf.feature, param=f"{name}_c{k}", typical=abs(b) or 1.0))
        columns += [c for c in lf.columns if c not in columns]
    formula = " + ".join(f"c{k} {f.symbol}" for k, f in enumerate(features, start=1))
    words = "; ".join(f.words for f in features)
    define(Spec(name, f"discovered form: {words}", tuple(columns), tuple(features)))
    return Proposal(name, formula, words, beta, r2, size, TERMS[name].source)


def proposed(candidates: list, model: tuple[str, ...], base, series, scheme,
             visited: frozenset = frozenset()) -> tuple[Proposal | None, list]:
    """The discovery stage, where no change helps and the residual has structure: a form the catalog lacks
    (:func:`propose`) for ``model`` fitted as ``base`` (:class:`.screen.Base`), scored, refitted on ``series``
    by ``scheme`` and ranked among the ``candidates``, unless it leads to a model in ``visited``.

    Returns
    -------
    ``(proposal or None, candidates)``, the candidates ranked (:func:`.screen.rank`).
    """
    proposal = propose(base.report.model, list(base.train), base.jacobian, base.residual, stride=base.stride)
    if proposal is None or frozenset(model + (proposal.term,)) in visited:
        return proposal, candidates
    cand = Candidate(proposal.term, model + (proposal.term,), kind="discovered", formula=proposal.formula,
                     source=proposal.source)
    cand = score_candidate(cand, base.report.model, list(base.train), base.jacobian, base.residual,
                           base.stride, base.free_run)
    params = [p.name for p in TERMS[proposal.term].parameters]
    found = {**dict(base.report.model.params), **dict(zip(params, proposal.coefficients))}
    cand = replace(cand, starts=(found, *cand.starts))
    if cand.confounded is None:
        cand = refit_candidate(cand, series, scheme, base.report, base.bic)
    cand = replace(cand, evidence=describe_discovered(cand, proposal, base.rmse_K))
    return proposal, sorted(candidates + [cand], key=rank)
