"""Many models at once, as arrays, so that a whole robot's (or a fleet's) actuators step together (the
Gymnasium wrapper, the monitor) exactly as :meth:`ThermalModel.simulate` steps each.

Each term gives its own contribution: its :meth:`~.terms.Term.combine` of its :meth:`~.terms.Term.forms`,
evaluated on one value per actuator with a parameter array per name, is the term's rise and gain for every
actuator at once, so the model's steady state under inputs held is ``(T_offset + sum rise) / (1 - sum gain)``
and its rate ``(1 - sum gain) / RC`` (Jorgensen et al.'s Eq. 5 with the model's terms). A slow mass
(:meth:`~.terms.Term.stage`) is a cascade stage, stepped as a first-order recursion of its own; a lagging
sensor (:meth:`~.terms.Term.output_lag_s`) lags the winding. A term whose heat goes into a slow mass
(``heats_slow_mass``) moves the temperature the stages settle to, as the ambient does.

A model steps here when every term of it does (:func:`steps_together`): its forms read only the effort and the
velocity, and it changes no slow mass's conductance; a term with a gain (copper's coefficient) does not step
with slow masses or a lag, whose recursions assume a rate the heat does not move. A new effect written with
``forms`` and ``combine`` steps here with no change to this module.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from .model import BASE_PARAMETERS, ThermalModel
from .terms import DEFAULT_MODEL, TERMS, Term

ARRAY_CHANNELS = frozenset({"effort", "velocity"})  # what a step of many actuators is given


class HeldInputs:
    """The inputs of many actuators at one instant, as a term's :meth:`~.terms.Term.forms` reads a log's: one
    value per actuator (``speed``, |velocity|, ``None``: no motion)."""

    current_A = None
    air_shift_K = 0.0

    __slots__ = ("effort", "speed")

    def __init__(self, effort: np.ndarray, speed: np.ndarray | None):
        self.effort, self.speed = effort, speed

    @property
    def velocity(self) -> np.ndarray:
        return np.zeros_like(self.effort) if self.speed is None else self.speed

    def channel(self, name: str) -> np.ndarray:
        if name == "effort":
            return self.effort
        if name == "velocity":
            return self.velocity
        raise KeyError(f"a step of many actuators is given effort and velocity, not {name}")

    def has(self, name: str) -> bool:
        return name in ARRAY_CHANNELS


def _arrayable(term: type[Term]) -> bool:
    """Whether a term steps in arrays: a slow mass, a lagging sensor, or forms of the effort and velocity
    alone."""
    if term.airflow_on is not None or not set(term.columns) <= ARRAY_CHANNELS:
        return False
    if term.carries_state:
        return term.stage is not Term.stage
    if term.lags_output:
        return term.output_lag_s is not Term.output_lag_s
    return term.forms is not Term.forms


def steps_together(model) -> bool:
    """Whether :class:`ModelArrays` steps ``model`` (module docstring): every term arrayable, a term with a
    gain not beside a slow mass or a lag, each slow mass after the masses it builds on."""
    terms = [TERMS[t] for t in model.terms]
    if not all(map(_arrayable, terms)):
        return False
    shaped = any(t.carries_state or t.lags_output for t in terms)
    if shaped and any(not (t.rise_only or t.carries_state or t.lags_output) for t in terms):
        return False
    order = list(model.terms)
    return all(order.index(r) < order.index(t.name) for t in terms for r in t.requires)


def one_node(model) -> bool:
    """Whether ``model`` steps together with no slow mass and no lag: its winding alone, exactly over any
    interval from its steady state and rate (the Gymnasium wrapper's step)."""
    shaped = any(TERMS[t].carries_state or TERMS[t].lags_output for t in model.terms)
    return steps_together(model) and not shaped


def _layout() -> tuple[tuple[str, float], ...]:
    """Every arrayable term's parameters with their nulls (a time constant's null 1 s, so that a stage of no
    share divides by nothing), after the base model's: the columns :meth:`ModelArrays.row` fills."""
    catalog = tuple(TERMS.items())
    if catalog != _LAYOUT[0]:
        names = [(p.name, 0.0) for p in BASE_PARAMETERS]
        for term in TERMS.values():
            if _arrayable(term):
                names += [(p.name, 1.0 if term.carries_state and p.unit == "s" else 0.0)
                          for p in term.parameters]
        _LAYOUT[:] = [catalog, tuple(names)]
    return _LAYOUT[1]


_LAYOUT: list = [(), ()]  # the catalog the layout was made for, and the layout


class ModelArrays:
    """The parameters of models that step together, one entry per model (a parameter a model lacks is its
    null): ``p[name]`` an array per parameter (also ``arrays.RC_s``, ``arrays.betaR_K_per_effort2``, ...),
    ``rc`` and ``offset`` the base model's.

    The robots' controllers plan with Jorgensen et al.'s Eq. 5 for many actuators at once (:meth:`of`,
    :meth:`from_specs`, :meth:`from_models`): the temperature a horizon ahead under efforts held (Eq. 25,
    :meth:`ahead`), as a quadratic in the effort (:meth:`ahead_coefficients`) and its derivative
    (:meth:`ahead_gradient`).
    """

    def __init__(self, models: Sequence = (), rows: np.ndarray | None = None):
        """From the models, or from their :meth:`row` stacked (a caller that steps the same models often keeps
        the rows)."""
        layout = _layout()
        columns = (np.array([self.row(m) for m in models], dtype=float).reshape(len(models), len(layout))
                   if rows is None else np.asarray(rows, dtype=float)).T
        self.p = {name: column for (name, _), column in zip(layout, columns)}
        self.rc, self.offset = self.p["RC_s"], self.p["T_offset_C"]
        present = {p.name for m in models for p in m.parameters} if rows is None else {
            name for (name, null), column in zip(layout, columns) if np.any(column != null)}
        self.terms = [cls() for cls in TERMS.values() if _arrayable(cls) and cls.parameters
                      and any(p.name in present for p in cls.parameters)]
        self.heats = [t for t in self.terms if not (t.carries_state or t.lags_output)]
        self.stages = [t for t in self.terms if t.carries_state]
        self.stage_names = [t.name for t in self.stages]  # the slow masses' nodes a state carries
        self.lags = [t for t in self.terms if t.lags_output]
        self.reads_speed = any("velocity" in t.columns for t in self.heats)  # whether a step needs |velocity|

    def __getattr__(self, name: str) -> np.ndarray:  # a parameter's array by its name: arrays.RC_s
        p = self.__dict__.get("p")
        if p is None or name not in p:
            raise AttributeError(f"{type(self).__name__} has no attribute or parameter {name!r}")
        return p[name]

    @property
    def n(self) -> int:
        return int(self.rc.shape[0])

    @classmethod
    def of(cls, **columns) -> "ModelArrays":
        """From parameter arrays by name, one entry per actuator (a parameter not given is its null):
        ``ModelArrays.of(RC_s=rc, betaR_K_per_effort2=beta, T_offset_C=offset)``."""
        layout = dict(_layout())
        unknown = sorted(set(columns) - set(layout))
        if unknown:
            raise ValueError(f"ModelArrays.of: no parameter {unknown} of a model that steps in arrays")
        arrays = {k: np.atleast_1d(np.asarray(v, dtype=float)) for k, v in columns.items()}
        n = arrays["RC_s"].shape[0]
        for name, arr in arrays.items():
            if arr.shape != (n,):
                raise ValueError(f"ModelArrays.of: {name} has shape {arr.shape}, expected ({n},)")
        if np.any(arrays["RC_s"] <= 0):
            raise ValueError(f"RC_s must be positive, got {arrays['RC_s']}")
        return cls(rows=np.column_stack([arrays.get(name, np.full(n, null))
                                         for name, null in layout.items()]))

    def replace(self, **columns) -> "ModelArrays":
        """The same models with the parameters named given new arrays (``T_offset_C=...``)."""
        kept = {k: v for k, v in self.p.items() if k in columns or self._given(k)}
        return type(self).of(**{**kept, **columns})

    def _given(self, name: str) -> bool:
        return bool(np.any(self.p[name] != dict(_layout())[name])) or name in ("RC_s", "T_offset_C")

    def subset(self, indices) -> "ModelArrays":
        """The models at ``indices`` (an index array or boolean mask), in that order."""
        return type(self)(rows=np.column_stack([self.p[name] for name, _ in _layout()])[indices])

    @classmethod
    def from_specs(cls, specs: Sequence, ambient_C: float = 25.0, lumped_nodes: int = 1) -> "ModelArrays":
        """Eq. 5 from actuator datasheets (:meth:`thermolimb.plant.ActuatorSpec.first_order`, no effort bias):
        what a controller can plan with before any log is identified."""
        rc, beta = zip(*(spec.first_order(lumped_nodes) for spec in specs))
        return cls.of(RC_s=np.array(rc), betaR_K_per_effort2=np.array(beta),
                      T_offset_C=np.full(len(rc), float(ambient_C)))

    @classmethod
    def from_models(cls, models: Sequence[ThermalModel]) -> "ModelArrays":
        """Stack fitted single-actuator models of Eq. 5 (terms within the default model's), for Eq. 25."""
        for m in models:
            extra = set(m.terms) - set(DEFAULT_MODEL)
            if extra:
                raise ValueError(f"from_models holds Eq. 5 only; model has extra terms {sorted(extra)} "
                                 f"(Eq. 25 plans with Eq. 5)")
        return cls(models)

    def equilibrium_C(self, effort: np.ndarray) -> np.ndarray:
        """Steady-state temperatures for efforts held forever (``effort``: ``(..., n)``)."""
        return self.forcing(effort)[0]

    def ahead(self, initial_C: np.ndarray, effort: np.ndarray, horizon_s: float | np.ndarray) -> np.ndarray:
        """Eq. 25: temperatures ``horizon_s`` ahead with efforts held constant (``effort``: ``(..., n)``)."""
        decay = np.exp(-np.asarray(horizon_s) / self.rc)
        return initial_C * decay + self.equilibrium_C(effort) * (1.0 - decay)

    def ahead_coefficients(self, initial_C: np.ndarray, horizon_s: float) -> tuple[np.ndarray, np.ndarray,
                                                                                    np.ndarray]:
        """``(a, b, c)`` with :meth:`ahead` ``= a + b F + c F^2`` per actuator: Eq. 25 as a quadratic in
        effort."""
        decay = np.exp(-np.asarray(horizon_s) / self.rc)
        b, c = self._quadratic()
        return initial_C * decay + self.offset * (1.0 - decay), b * (1.0 - decay), c * (1.0 - decay)

    def ahead_gradient(self, effort: np.ndarray, horizon_s: float | np.ndarray) -> np.ndarray:
        """d T_i(horizon) / d F_i (the Jacobian is diagonal), same shape as ``effort``."""
        decay = np.exp(-np.asarray(horizon_s) / self.rc)
        b, c = self._quadratic()
        return (2.0 * effort * c + b) * (1.0 - decay)

    def _quadratic(self) -> tuple[np.ndarray, np.ndarray]:
        """The steady rise's coefficients of the effort and of its square, each term's from its own rise at
        efforts 1 and -1 (Eq. 5's terms are even or odd in the effort; no other model is planned with Eq. 25).
        """
        if any(t.name not in DEFAULT_MODEL for t in self.heats) or self.stages or self.lags:
            raise ValueError("Eq. 25 as a quadratic in effort holds for Eq. 5's models only")
        up, down = HeldInputs(np.ones(self.n), None), HeldInputs(-np.ones(self.n), None)
        b, c = 0.0, 0.0
        for term in self.heats:
            r1, r2 = term.combine(self.p, term.forms(up))[0], term.combine(self.p, term.forms(down))[0]
            b, c = b + (r1 - r2) / 2.0, c + (r1 + r2) / 2.0
        return b, c

    @staticmethod
    def row(model) -> tuple:
        """A model's parameters in the order the arrays hold them (a parameter it lacks is its null)."""
        return tuple(model.params.get(name, null) for name, null in _layout())

    def forcing(self, effort: np.ndarray, speed: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """``(steady_C, rate_per_s)`` each model heads for under ``effort`` (and ``speed``, |velocity|) held
        (its ``dT/dt = rate (steady - T)``)."""
        inputs = HeldInputs(effort, speed)
        rise, gain = 0.0, 0.0
        for term in self.heats:
            r, g = term.combine(self.p, term.forms(inputs))
            rise, gain = rise + r, gain + g
        if not (gain.any() if isinstance(gain, np.ndarray) else gain):
            return self.offset + rise, 1.0 / self.rc
        restoring = np.maximum(1.0 - gain, 1e-6)
        return (self.offset + rise) / restoring, restoring / self.rc

    def boundary(self, effort: np.ndarray, speed: np.ndarray | None) -> np.ndarray:
        """The temperature the slow masses settle to: the offset, and the heat put into them."""
        inputs, out = HeldInputs(effort, speed), self.offset
        for term in self.heats:
            if term.heats_slow_mass:
                out = out + term.combine(self.p, term.forms(inputs))[0]
        return out

    def step(self, state: dict, dt: np.ndarray, effort: np.ndarray, speed: np.ndarray | None) -> dict:
        """One interval ``dt`` from ``state`` (arrays ``winding``, ``output`` and each slow mass's node, by
        its term's name) under the first sample's inputs held, as ``simulate`` carries a run on: the new
        state, and the ``steady_C`` and ``rate_per_s`` of the second sample's inputs. ``effort`` and
        ``speed``: (n, 2)."""
        u0, rate0 = self.forcing(effort[:, 0], None if speed is None else speed[:, 0])
        u1, rate1 = self.forcing(effort[:, 1], None if speed is None else speed[:, 1])
        shaped, out = u0, {}
        boundary = self.boundary(effort[:, 0], None if speed is None else speed[:, 0])
        for term in self.stages:
            phi, tau = term.stage(self.p)
            heat = shaped - boundary
            a = np.exp(-dt / tau)
            node = state.get(term.name, self.offset)
            out[term.name] = a * node + (1.0 - a) * (boundary + phi * heat)
            shaped = node + (1.0 - phi) * heat  # the stage's shaping of the first sample
        a = np.exp(-np.broadcast_to(rate0, dt.shape) * dt)
        winding = a * state["winding"] + (1.0 - a) * shaped
        output = winding
        for term in self.lags:
            sensor_tau = term.output_lag_s(self.p)
            lag = sensor_tau > 0.0
            tau = np.where(lag, sensor_tau, 1.0)
            a = np.exp(-dt / tau)
            lagged = a * state["output"] + (1.0 - a) * state["winding"] + (1.0 - tau / dt * (1.0 - a)) * (
                winding - state["winding"])
            output = np.where(lag, lagged, winding)
        out.update(winding=winding, output=output, steady_C=u1, rate_per_s=np.broadcast_to(rate1, dt.shape))
        return out
