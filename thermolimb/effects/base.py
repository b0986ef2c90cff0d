"""What one physical effect is to the suite, in one object: :class:`Effect`.

An effect (speed losses, copper's temperature coefficient, a lagging sensor, a fan) is known four ways:

* the **model's term** (:class:`~thermolimb.model.terms.Term`), which ``fit`` and ``diagnose`` fit and
  ``--model`` names;
* the **residual's sign of it**: which of the residual's correlations with the log's channels speaks for it
  (``"|velocity|"`` for speed losses), or one of :data:`PHASES` when its signature is in time or temperature;
* the **plant's realisation** (:class:`PlantEffect`): how the rig's thermal plant makes the physics happen, as
  hooks :class:`~thermolimb.plant.ThermalPlant` calls on every effect that is on;
* the **hidden case** (:class:`Hidden`): the plant log that hides it, to prove the diagnosis finds it.

Each lives in one module of this package, which registers an :class:`Effect` holding all four; the rest of
the suite reaches an effect by its catalog name (``EFFECTS["speed_losses"]``) and never keeps a table of
its own keyed by effect names.  ``docs/architecture.md`` has the steps for a new effect.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from ..model.terms import Parameter, Term
from ..util.errors import UsageError

# effects whose signature is in time or temperature, not in one input channel: what the residual shows of them
HOT_AND_COOL = "the fit hot against cool"  # copper's tempco: the model is worse when hot
SLOW_DRIFT = "a slow drift"  # a slow mass: the residual stays correlated over long lags
ONSETS = "errors at heating and cooling onsets"  # a lagging sensor
PHASES = (HOT_AND_COOL, SLOW_DRIFT, ONSETS)


@dataclass(frozen=True)
class Schedule:
    """A logged channel that holds a random level for a random time, then switches (a fan's duty, a brake).

    ``levels`` are the values it takes; each is held for a time drawn
    uniformly from ``hold_s``.  Every actuator has its own schedule, drawn
    from the plant's generator (so a seed gives the same schedules).
    """

    levels: tuple[float, ...]
    hold_s: tuple[float, float] = (300.0, 900.0)


@dataclass(frozen=True)
class PlantEffect:
    """How the plant realises an effect: a frozen dataclass of its parameters (SI units in the names) whose
    hooks :class:`~thermolimb.plant.ThermalPlant` calls on every effect that is on, in the registry's order.
    Every hook does nothing by default; an effect overrides the ones its physics touches.

    ``net`` is the plant's layout (:class:`~thermolimb.plant.plant.Layout`: node indices per actuator, the
    system matrix ``A``, the inverse capacities, each outer node's conductance to ambient).
    """

    name: ClassVar[str]
    sensor_node: ClassVar[bool] = False  # each actuator's thermistor is a state node of its own (a lag)
    state_dependent: ClassVar[bool] = False  # its heat depends on the network's state: no free blocks
    draws_random: ClassVar[bool] = False  # draws from the plant's generator (noise, schedules)

    def check(self, specs) -> None:
        """Refuse actuators this effect cannot act on (a ``ValueError`` naming what is missing)."""

    def wire(self, net) -> None:
        """Change the network's structure: ``net.A`` in place (conduction between nodes, a sensor's lag)."""

    def torque_effort(self, effort: np.ndarray) -> np.ndarray:
        """The share of the effort the motor's torque current makes (a series-elastic bias takes some)."""
        return effort

    @property
    def bias_effort(self) -> float:
        """Effort the motor does not make, which protection's derating leaves alone (N m or N)."""
        return 0.0

    def extra_current_A(self, speed: np.ndarray, share) -> np.ndarray | float:
        """Current that makes no torque (A), at each speed; ``share``: protection's cap on the whole
        current."""
        return 0.0

    def place_joule(self, net, joule: np.ndarray, constant: np.ndarray, per_kelvin: np.ndarray) -> bool:
        """Put the winding's Joule heat ``joule`` (W at the reference temperature) into the nodes itself, as a
        resistance that changes with temperature does, and say so (``True``); by default the plant does."""
        return False

    def heat(self, net, at, constant: np.ndarray, per_kelvin: np.ndarray) -> None:
        """Add this effect's heat into the nodes, as ``constant + per_kelvin * x`` (W and W/K): ``at`` holds
        ``speed`` (rad/s, per actuator), ``time_s``, ``ambient_C`` and the plant's ``schedules``."""

    def ambient_C(self, start_C: float, time_s: float) -> float | None:
        """The ambient at ``time_s`` when this effect moves it (``None``: it does not)."""
        return None

    def schedules(self) -> dict[str, Schedule]:
        """The random schedules this effect's logged channels follow, by key."""
        return {}

    def logged(self, plant) -> dict[str, np.ndarray]:
        """The extra channels this effect logs now, by column name (unit in the name), per actuator."""
        return {}


@dataclass(frozen=True)
class Hidden:
    """The plant log that hides an effect: the plant effect switched on (``effect``; ``None``: none, as the
    X8's own slow masses need), the load scale that makes it show, the plant's options, and ``also``: terms
    that name the same physics acting elsewhere in the model (airflow on the housing)."""

    case: str  # the case's name in tables and benchmarks
    effect: str | None
    load_scale: float = 1.0
    options: dict = field(default_factory=dict)
    also: tuple[str, ...] = ()


@dataclass(frozen=True)
class Effect:
    """Everything the suite knows about one physical effect (module docstring), by its catalog name."""

    name: str
    term: type[Term] | None = None  # the model's term, registered in the catalog under ``name``
    plant: type[PlantEffect] | None = None  # the plant's realisation (its own ``name``: the plant's switch)
    # the residual's correlation that speaks for it (a channel: "|velocity|"; "temperature of" for any
    # neighbour's), or one of PHASES; None: the correlation with the term's first column
    residual: str | None = None
    hidden: Hidden | None = None
    # the log channel the effect rides on, which must move in the data it is fitted on and judged on
    # (:func:`thermolimb.workbench.excitation.channel_excitation`); None: the effort and time, as the base
    # model's
    rides: str | None = None


EFFECTS: dict[str, Effect] = {}
# by the plant's switch name, in the order the plant applies them
PLANT_EFFECTS: dict[str, type[PlantEffect]] = {}


def register(*effects: Effect) -> None:
    """Register effects (each module of this package calls this once for what it defines)."""
    for effect in effects:
        EFFECTS[effect.name] = effect
        if effect.plant is not None:
            PLANT_EFFECTS[effect.plant.name] = effect.plant


class PlantEffects:
    """Which plant effects are on: one instance per effect switched on, by its switch name; every other
    known effect reads as ``None`` (``effects.sensor_lag is None``: off).

    ``PlantEffects(sensor_noise=SensorNoise(), quantisation=Quantisation())``; ``effects.replace(...)`` for a
    changed copy; ``PlantEffects.from_names("speed_losses,sensor_noise")`` with default parameters.
    """

    __slots__ = ("_on",)

    def __init__(self, **on: PlantEffect | None):
        unknown = [n for n in on if n not in PLANT_EFFECTS]
        if unknown:
            raise TypeError(f"PlantEffects got unknown effect(s) {unknown}; "
                            f"known effects: {', '.join(PLANT_EFFECTS)}")
        for name, value in on.items():
            if value is not None and not isinstance(value, PLANT_EFFECTS[name]):
                raise TypeError(f"PlantEffects({name}=...) needs a {PLANT_EFFECTS[name].__name__}, got "
                                f"{type(value).__name__}")
        object.__setattr__(self, "_on", {n: on[n] for n in PLANT_EFFECTS if on.get(n) is not None})

    def __getattr__(self, name: str):
        if name in PLANT_EFFECTS:
            return self._on.get(name)
        raise AttributeError(
            f"PlantEffects has no effect {name!r}; known effects: {', '.join(PLANT_EFFECTS)}"
        )

    def __setattr__(self, name, value):
        raise AttributeError("PlantEffects is read-only; make a changed copy with .replace(...)")

    def __eq__(self, other) -> bool:
        return isinstance(other, PlantEffects) and self._on == other._on

    def __hash__(self) -> int:
        return hash(tuple(self._on.items()))

    def __repr__(self) -> str:
        return f"PlantEffects({', '.join(f'{n}={v!r}' for n, v in self._on.items())})"

    def __reduce__(self):  # picklable (plants cross process boundaries in fleets)
        return (_rebuild, (tuple(self._on.items()),))

    def replace(self, **changes: PlantEffect | None) -> "PlantEffects":
        """A copy with some effects switched on, changed, or off (``None``)."""
        return PlantEffects(**{**self._on, **changes})

    @property
    def active(self) -> tuple[PlantEffect, ...]:
        """The effects that are on, in the order the plant applies them."""
        return tuple(self._on.values())

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(self._on)

    @property
    def bias_effort(self) -> float:
        """Effort the motors do not make (a series-elastic bias), N m or N."""
        return sum((fx.bias_effort for fx in self.active), 0.0)

    @classmethod
    def from_names(cls, names) -> "PlantEffects":
        """Effects switched on by name, with default parameters; ``"none"`` or empty for none."""
        if isinstance(names, str):
            names = [n.strip() for n in names.split(",")]
        names = [n for n in names if n and n != "none"]
        unknown = [n for n in names if n not in PLANT_EFFECTS]
        if unknown:
            raise UsageError(f"unknown plant effect(s) {unknown}; known effects: {', '.join(PLANT_EFFECTS)}")
        return cls(**{n: PLANT_EFFECTS[n]() for n in names})

    @classmethod
    def realistic_sensor(cls) -> "PlantEffects":
        """Only what every real reading has: noise and 0.1 degC quantisation."""
        return cls.from_names(("sensor_noise", "quantisation"))


def _rebuild(items) -> PlantEffects:
    return PlantEffects(**dict(items))


def speed(s) -> np.ndarray:
    """|velocity| of a term's signals."""
    return np.abs(s.channel("velocity"))


def airflow_parameter(name: str, conductance: str, when: str) -> Parameter:
    """The gain of airflow on a conductance to ambient: it times ``1 + gain |v|``."""
    return Parameter(name, "1/({velocity})", 0.0, 20.0, 0.3, "relative increase of "
                                                             f"{conductance} per unit speed",
                     f"motion at several speeds while {when}", plausible=(0.0, 5.0))
