"""Composable terms of the effort-based thermal model, and their registry.

The model of one actuator is Jorgensen et al.'s Eq. 5 written with extra terms:

    RC * dT/dt + T = T_offset + sum_k ( rise_k(t) + gain_k(t) * T )

Each term contributes a *rise* in kelvin (a steady-state temperature rise it
would cause on its own) and optionally a *gain* (dimensionless) multiplying the
temperature itself, which is how temperature-dependent effects (copper
resistance, cooling that depends on motion) enter while the model stays a
first-order linear ODE in T at every instant.

A new effect is a subclass of :class:`Term` with a ``name``, its
``parameters`` (with units and bounds), the log ``columns`` it needs, and a
``contribution`` method -- or, when the contribution combines arrays of the log
linearly, ``forms`` and ``combine``, which a long log's fit averages once per
block (:mod:`.block_means`); decorate it with :func:`register_term` and every
estimator, ``thermolimb fit`` and ``thermolimb diagnose`` can use it.
"""

from __future__ import annotations

import inspect
import re
from dataclasses import dataclass
from typing import ClassVar, Mapping

import numpy as np

from ..util.errors import ModelSpecError
from .parameter_units import render, spaced
from .signals import Signals

LONG_TIME_CONSTANT = 3.0  # a time constant longer than this many run durations is extrapolated, not seen


@dataclass(frozen=True)
class Parameter:
    """One model parameter: its name (unit in the name), unit, bounds and typical size."""

    name: str
    unit: str
    lower: float
    upper: float
    typical: float  # order of magnitude, used for scaling and as a starting value
    description: str
    excitation: str = "inputs that vary independently of the other terms'"  # what a log needs to identify it
    null: float = 0.0  # the value at which the effect is absent (for score tests)
    nuisance: bool = False  # only meaningful once the effect is present (e.g. a second mass's time constant)
    plausible: tuple[float, float] | None = None  # the physically expected range, for a plausibility check
    # a fit keeps it within this many times the longest run it sees (None: no limit)
    within_runs: float | None = None

    def unit_in(self, units: Mapping[str, str] | None) -> str:
        """The unit with the log's channel units put in (``unit`` may name channels: ``K/({effort})^2``)."""
        return render(self.unit, units)


class Term:
    """Base class of a model term (see the module docstring)."""

    name: ClassVar[str]
    description: ClassVar[str]
    # a few words a reader knows ("speed losses"); the name with spaces if not given
    label: ClassVar[str] = ""
    parameters: ClassVar[tuple[Parameter, ...]] = ()
    columns: ClassVar[tuple[str, ...]] = ("effort",)
    is_heat_source: ClassVar[bool] = False
    # a heat source that is a resistance's Joule heat, I^2 R, from the square of this channel ("effort",
    # "current"), its first parameter the gain: what a motor model that heats by its current (MuJoCo's
    # dcmotor) can carry
    squared_channel: ClassVar[str | None] = None
    # copper's coefficient: the Joule heat times 1 + p (T - 25 degC), p its first parameter (1/K)
    scales_resistance: ClassVar[bool] = False
    # after this term the offset is no ambient temperature (it moves the boundary to a measured one, or with
    # one)
    redefines_offset: ClassVar[bool] = False
    # a boundary term moves the temperature heat finally flows to (the ambient): it reaches the winding
    # through every slow mass, where a heat term's rise builds up partly across each
    boundary: ClassVar[bool] = False
    # a heat put into the slow mass (friction in the housing): its whole rise reaches the winding through the
    # slow masses, as the boundary's does, while the offset stays the ambient (it needs a slow mass:
    # ``requires``)
    heats_slow_mass: ClassVar[bool] = False
    requires: ClassVar[tuple[str, ...]] = ()  # terms this one builds on (a third mass needs a second)
    # written by a diagnosis (thermolimb.model.generated), not offered by the catalog
    generated: ClassVar[bool] = False
    # a term with a thermal state of its own (a slow mass) takes ``state=`` in shape_equilibrium, the value an
    # earlier piece of the run ended with, and leaves its last value in ``self.state``
    carries_state: ClassVar[bool] = False
    # a term whose output lags the winding (a thermistor's lag): the winding's start is then a hidden state
    # too
    lags_output: ClassVar[bool] = False
    # a term whose parameters move only the rise (its gain is 0 and it shapes no state and no output): the
    # model's response to a hidden state's start does not depend on them (ThermalModel.place_hidden reuses it)
    rise_only: ClassVar[bool] = False
    # parameters of other terms its contribution reads (copper's coefficient scales the Joule heat): the model
    # is then not affine in them, whatever their own term (ThermalModel.place_hidden may not reuse responses
    # across them)
    reads: ClassVar[tuple[str, ...]] = ()
    # a term that changes a slow mass's conductance to ambient (airflow on the housing, a fan's duty) names
    # that mass's term; :meth:`airflow_gain` is by how much, and the term adds no heat of its own
    airflow_on: ClassVar[str | None] = None

    def contribution(
        self, p: Mapping[str, float], s: Signals
    ) -> tuple[np.ndarray | float, np.ndarray | float]:
        """Return ``(rise_K, gain)`` per sample for parameter values ``p`` (all of the model's); default:
        :meth:`combine` of :meth:`forms`, or none."""
        forms = self.forms(s)
        return (0.0, 0.0) if forms is None else self.combine(p, forms)

    def forms(self, s: Signals) -> tuple[np.ndarray, ...] | None:
        """The per-sample arrays the contribution combines linearly, whatever the parameters (``effort**2``,
        ``|velocity|``), or ``None`` for a term that defines :meth:`contribution` itself.  A block-averaged
        run (:mod:`.block_means`) averages them once, not each contribution."""
        return None

    def combine(self, p: Mapping[str, float], forms: tuple) -> tuple[np.ndarray | float, np.ndarray | float]:
        """``(rise_K, gain)`` from :meth:`forms`' arrays (or their block means), linear in them."""
        raise NotImplementedError  # abstract: a term with forms combines them

    def shape_equilibrium(self, p: Mapping[str, float], s: Signals, equilibrium_C: np.ndarray,
                          initial_C: float, boundary_C: np.ndarray) -> np.ndarray:
        """Terms that add thermal states may reshape the winding's equilibrium; default: unchanged.

        ``initial_C`` is the temperature the simulation starts from, ``boundary_C``
        the temperature heat finally flows to (offset and boundary terms), per sample.
        """
        return equilibrium_C

    def stage(self, p: Mapping[str, float]) -> tuple | None:
        """For a slow mass (``carries_state``): its share of the rise and its time constant (s), a cascade
        stage of the model (:mod:`.arrays` steps it for many actuators at once); default: none."""
        return None

    def output_lag_s(self, p: Mapping[str, float]) -> float | None:
        """For a term that lags the output (``lags_output``): the reading's time constant (s); default:
        none."""
        return None

    def winding_share(self, p: Mapping[str, float]) -> float:
        """Share of a heat's rise that builds up across the winding itself (a slow mass takes the rest);
        default 1."""
        return 1.0

    def shape_output(self, p: Mapping[str, float], s: Signals, winding_C: np.ndarray,
                     measured_initial_C: float) -> np.ndarray:
        """Terms that change what the sensor reports (e.g. its lag); default: the winding temperature."""
        return winding_C

    def initial_winding(self, p: Mapping[str, float], measured_C: float, rate_K_per_s: float) -> float:
        """The winding temperature behind a reading ``measured_C`` that is moving at ``rate_K_per_s``."""
        return measured_C

    def airflow_gain(self, p: Mapping[str, float], s: Signals) -> np.ndarray | float:
        """For a term with ``airflow_on``: the increase of that mass's conductance to ambient, as a multiple
        of its still-air value, per sample (the conductance is ``1 + airflow_gain`` times it); default 0."""
        return 0.0

    def implausible(self, p: Mapping[str, float], units: Mapping[str, str] | None = None) -> str | None:
        """Why fitted values are physically implausible, or ``None``; default: each parameter's range.

        ``units`` are the log's channel units, put into the parameters' units when given.
        """
        for par in self.parameters:
            if par.plausible and not (par.plausible[0] <= p[par.name] <= par.plausible[1]):
                return (f"{par.name} = {p[par.name]:.3g}{spaced(par.unit_in(units))} is outside "
                        f"{par.plausible[0]:g}..{par.plausible[1]:g}")
        return None

    def features(self, s: Signals, temperature_C: np.ndarray) -> np.ndarray | None:
        """Regressors ``X`` with ``rise + gain*T == X @ [p[name] for name in parameters]``.

        Terms linear in their parameters return them (used by the regression
        estimators); others return ``None`` and are identified by output error.
        ``temperature_C`` is the measured (filtered) temperature, for terms
        whose contribution depends on it.
        """
        return None


class LinearTerm(Term):
    """A term whose rise is its one parameter times a regressor built from the log (linear in that
    parameter)."""

    rise_only = True

    def regressor(self, s: Signals) -> np.ndarray:
        raise NotImplementedError  # abstract

    def forms(self, s):
        return (self.regressor(s),)

    def combine(self, p, forms):
        return p[self.parameters[0].name] * forms[0], 0.0

    def features(self, s, temperature_C):
        return self.regressor(s)[:, None]


TERMS: dict[str, type[Term]] = {}
BUILT_IN = "thermolimb.effects."  # the package of the built-in terms, which no other term may replace


def is_built_in(cls: type[Term]) -> bool:
    return cls.__module__.startswith(BUILT_IN)


def implausibility(term: Term, p: Mapping[str, float], units: Mapping[str, str] | None) -> str | None:
    """``term.implausible`` with the log's channel units, from a term written to take them (a user's term, or
    one generated before terms took units, is asked with the values alone)."""
    if "units" in inspect.signature(term.implausible).parameters:
        return term.implausible(p, units=units)
    return term.implausible(p)


def terms_in(p: Mapping[str, float]) -> list[type[Term]]:
    """The term classes with parameters of the model whose values are ``p`` (a model's parameter names are its
    terms': a term is in it when its parameters are).  Kept per set of names while the catalog holds the same
    terms: a slow mass asks at every simulation (UR3 J5's diagnosis: 46,000 times, 16 us each by the scan)."""
    catalog = tuple(TERMS.items())
    if catalog != _TERMS_IN[0]:
        _TERMS_IN[:] = [catalog, {}]
    names = frozenset(p)
    found = _TERMS_IN[1].get(names)
    if found is None:
        found = _TERMS_IN[1][names] = tuple(
            cls for cls in TERMS.values() if cls.parameters and all(q.name in names for q in cls.parameters)
        )
    return list(found)


_TERMS_IN: list = [(), {}]  # the catalog the answers were found in, and the answers by parameter names


def airflow_terms(mass: str, p: Mapping[str, float]) -> list[Term]:
    """The terms of the model whose values are ``p`` that change the conductance of the slow mass ``mass``."""
    return [cls() for cls in terms_in(p) if cls.airflow_on == mass]


def register_term(cls: type[Term]) -> type[Term]:
    """Class decorator: add a term to the catalog under ``cls.name``."""
    if not getattr(cls, "name", None):
        raise ValueError(f"{cls.__name__} needs a 'name' to be registered")
    earlier = TERMS.get(cls.name)
    if earlier is not None and is_built_in(earlier) and not is_built_in(cls):
        raise ValueError(f"term '{cls.name}' would replace the built-in "
                         f"term of that name ({earlier.description}); "
                         f"give yours another name")
    clashes = {p.name for p in cls.parameters} & ({"RC_s", "T_offset_C"} | _parameter_names_except(cls.name))
    if clashes:
        raise ValueError(f"term '{cls.name}' reuses parameter names {sorted(clashes)} of another term")
    for p in cls.parameters:
        numbers = (p.lower, p.upper, p.typical)
        if any(isinstance(v, bool) or not isinstance(v, (int, float)) or v != v for v in numbers) \
                or not p.lower < p.upper or not p.lower <= p.typical <= p.upper:
            raise ValueError(f"term '{cls.name}': parameter {p.name} "
                             "needs lower < upper and lower <= typical <= "
                             f"upper, got lower {p.lower!r}, upper {p.upper!r}, typical {p.typical!r}")
    TERMS[cls.name] = cls
    return cls


def unregister_term(name: str) -> None:
    """Remove a term from the catalog (e.g. a user's experiment, when done with it)."""
    if name not in TERMS:
        raise KeyError(f"no registered term {name!r}")
    del TERMS[name]


def effect_label(name: str) -> str:
    """The words a reader knows for a term: its ``label``, "a discovered form" for a discovered one, else its
    name with spaces."""
    term = TERMS.get(name)
    if term is not None and term.label:
        return term.label
    if name.startswith("discovered_"):  # a channel's generated term (brake_heat) keeps its name, in words
        return "a discovered form"
    return name.replace("_", " ")


def readable(text: str) -> str:
    """Effect identifiers in ``text`` with the words a reader knows before them: ``+ speed_losses`` -> ``+
    speed losses (speed_losses)``; a comma-joined model, ``joule,effort_bias`` -> ``Joule heating from effort,
    effort bias (joule,effort_bias)``."""
    known = sorted(TERMS, key=len, reverse=True)
    word = r"(?:discovered_\w+?|" + "|".join(map(re.escape, known)) + r")(?![\w])"
    pattern = re.compile(rf"(?<![\w])({word}(?:,{word})*)")

    def one(m: re.Match) -> str:
        names = m.group(1).split(",")
        if any(re.search(r"_c\d+$", n) for n in names):  # a generated term's parameter, not a term
            return m.group(1)
        named = [n for n in names if (TERMS[n].label if n in TERMS else None) or n.startswith("discovered_")]
        if not named:  # no words beyond the name (a user's term, a channel's): the name alone
            return m.group(1)
        return f"{', '.join(effect_label(n) for n in names)} ({m.group(1)})"

    # a discovered form's label already says so: "+ discovered_x (discovered)" is not told twice
    return re.sub(r"(a discovered form \(discovered_\w+\)) \(discovered\)", r"\1", pattern.sub(one, text))


def _parameter_names_except(name: str) -> set[str]:
    return {p.name for key, t in TERMS.items() if key != name for p in t.parameters}


DEFAULT_MODEL = ("joule", "effort_bias")


def parse_model(spec: str | tuple[str, ...] | list[str]) -> tuple[str, ...]:
    """Validate a comma-separated model description, e.g. ``"joule,effort_bias"``."""
    names = [n.strip() for n in spec.split(",")] if isinstance(spec, str) else [str(n).strip() for n in spec]
    names = [n for n in names if n]
    if not names:
        raise ModelSpecError(f"empty model; expected comma-separated terms from: {', '.join(TERMS)}")
    unknown = [n for n in names if n not in TERMS]
    if unknown:
        raise ModelSpecError(
            f"unknown model term(s) {', '.join(repr(u) for u in unknown)}; known terms: {', '.join(TERMS)}"
        )
    if len(set(names)) != len(names):
        raise ModelSpecError(f"model lists a term twice: {','.join(names)}")
    for n in names:
        missing = [r for r in TERMS[n].requires if r not in names]
        if missing:
            raise ModelSpecError(f"model term '{n}' builds on {', '.join(missing)}; add it: "
                                 f"{','.join(names[:names.index(n)] + missing + names[names.index(n):])}")
    if not any(TERMS[n].is_heat_source for n in names):
        sources = [n for n, t in TERMS.items() if t.is_heat_source]
        raise ModelSpecError(f"model {','.join(names)} has no heat source; add one of: {', '.join(sources)}")
    return tuple(names)
