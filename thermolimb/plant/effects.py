"""Physical effects of the plant beyond the effort-squared heating, each switchable.

Every effect is a frozen dataclass of its parameters (units in the names); a
:class:`PlantEffects` holds one instance per effect that is on, ``None`` for
off.  Default values are chosen to be of a plausible size for an X8-class
actuator and are documented on each field.
"""

from __future__ import annotations

from dataclasses import dataclass, fields, replace

from ..constants import COPPER_REFERENCE_C, COPPER_TEMPCO_PER_K
from ..util.errors import UsageError


@dataclass(frozen=True)
class EffortBias:
    """Series-elastic bias: the motor current makes ``effort - bias_effort`` (seed Eq. 2)."""

    bias_effort: float = 2.0  # N m (or N)


@dataclass(frozen=True)
class WindingTempco:
    """Copper resistance rising with winding temperature: R = R25 (1 + alpha (T - 25 degC))."""

    alpha_per_K: float = COPPER_TEMPCO_PER_K
    reference_C: float = COPPER_REFERENCE_C


@dataclass(frozen=True)
class SpeedLosses:
    """Losses growing with output speed: bearing/gear friction (into the housing) and iron losses (winding)."""

    friction_W_per_rad_s: float = 1.5  # W per rad/s of |velocity|
    iron_W_per_rad2_s2: float = 2.0  # W per (rad/s)^2


@dataclass(frozen=True)
class FieldWeakening:
    """Current that makes no torque: d-axis current above a base speed, i_d = k (|v| - v_base)."""

    base_speed_rad_s: float = 0.8
    current_A_per_rad_s: float = 1.5


@dataclass(frozen=True)
class NeighborCoupling:
    """Conduction between the outer nodes of neighbouring actuators (consecutive in the plant's order)."""

    conductance_W_per_K: float = 0.3


@dataclass(frozen=True)
class AmbientVariation:
    """Ambient temperature drifting and oscillating: T_amb(t) = T0 + drift t + A sin(2 pi t / period)."""

    amplitude_K: float = 3.0
    period_s: float = 2400.0
    drift_K_per_h: float = 2.0


@dataclass(frozen=True)
class MotionCooling:
    """Airflow while moving: the outer node's conductance to ambient times (1 + gain |v|)."""

    gain_per_rad_s: float = 0.6


@dataclass(frozen=True)
class SensorLag:
    """The thermistor follows the winding with a first-order lag."""

    time_constant_s: float = 15.0


@dataclass(frozen=True)
class SensorNoise:
    """White Gaussian noise on every temperature reading."""

    std_K: float = 0.05


@dataclass(frozen=True)
class Quantisation:
    """Readings are rounded to a step."""

    step_K: float = 0.1


@dataclass(frozen=True)
class PlantEffects:
    """Which effects are on (an instance) or off (``None``)."""

    effort_bias: EffortBias | None = None
    winding_tempco: WindingTempco | None = None
    speed_losses: SpeedLosses | None = None
    field_weakening: FieldWeakening | None = None
    neighbor_coupling: NeighborCoupling | None = None
    ambient_variation: AmbientVariation | None = None
    motion_cooling: MotionCooling | None = None
    sensor_lag: SensorLag | None = None
    sensor_noise: SensorNoise | None = None
    quantisation: Quantisation | None = None

    @classmethod
    def from_names(cls, names) -> "PlantEffects":
        """Effects switched on by name, with default parameters; ``"none"`` or empty for none."""
        if isinstance(names, str):
            names = [n.strip() for n in names.split(",")]
        names = [n for n in names if n and n != "none"]
        unknown = [n for n in names if n not in EFFECT_TYPES]
        if unknown:
            raise UsageError(f"unknown plant effect(s) {unknown}; known effects: {', '.join(EFFECT_TYPES)}")
        return replace(cls(), **{n: EFFECT_TYPES[n]() for n in names})

    @classmethod
    def realistic_sensor(cls) -> "PlantEffects":
        """Only what every real reading has: noise and 0.1 degC quantisation."""
        return cls(sensor_noise=SensorNoise(), quantisation=Quantisation())

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(f.name for f in fields(self) if getattr(self, f.name) is not None)


EFFECT_TYPES = {
    "effort_bias": EffortBias,
    "winding_tempco": WindingTempco,
    "speed_losses": SpeedLosses,
    "field_weakening": FieldWeakening,
    "neighbor_coupling": NeighborCoupling,
    "ambient_variation": AmbientVariation,
    "motion_cooling": MotionCooling,
    "sensor_lag": SensorLag,
    "sensor_noise": SensorNoise,
    "quantisation": Quantisation,
}
