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
    """Series-elastic bias: the motor current makes ``effort - bias_effort`` (Jorgensen et al., Eq. 2)."""

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
class Schedule:
    """A logged channel that holds a random level for a random time, then switches (a fan's duty, a brake).

    ``levels`` are the values it takes; each is held for a time drawn
    uniformly from ``hold_s``.  Every actuator has its own schedule, drawn
    from the plant's generator (so a seed gives the same schedules).
    """

    levels: tuple[float, ...]
    hold_s: tuple[float, float] = (300.0, 900.0)


@dataclass(frozen=True)
class FanCooling:
    """A fan whose duty (logged as ``fan [%]``) multiplies the outer node's conductance to ambient by
    ``1 + gain * duty``.  The model's catalog has no fan: its one channel is the logged duty."""

    gain: float = 1.0
    schedule: Schedule = Schedule((0.0, 0.25, 0.5, 0.75, 1.0))
    column: str = "fan [%]"
    scale: float = 100.0  # logged value per unit of duty


@dataclass(frozen=True)
class HoldingBrake:
    """A holding brake whose coil heats the winding while engaged (logged as ``brake [1]``, 1 engaged)."""

    coil_W: float = 3.0
    schedule: Schedule = Schedule((0.0, 1.0), hold_s=(120.0, 600.0))
    column: str = "brake [1]"
    scale: float = 1.0


@dataclass(frozen=True)
class DriverConduction:
    """The driver board conducts into the winding (``conductance_W_per_K``) and carries an electronics load of
    its own that switches between ``schedule.levels`` (W); its thermistor is logged as ``driver [degC]``.
    Needs actuators with a driver board (:class:`~thermolimb.plant.network.DriverSpec`)."""

    conductance_W_per_K: float = 0.15
    schedule: Schedule = Schedule((0.0, 2.0, 4.0, 6.0))
    column: str = "driver [degC]"


@dataclass(frozen=True)
class DecoyChannels:
    """Channels that vary and do nothing thermal: a supply voltage (``supply [V]``) and an indicator (``led [1]``).
    For checking that a diagnosis does not take a channel that only varies."""

    supply: Schedule = Schedule((23.0, 23.5, 24.0, 24.5, 25.0), hold_s=(200.0, 800.0))
    led: Schedule = Schedule((0.0, 1.0), hold_s=(120.0, 600.0))


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
    fan_cooling: FanCooling | None = None
    holding_brake: HoldingBrake | None = None
    driver_conduction: DriverConduction | None = None
    decoy_channels: DecoyChannels | None = None

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
    "fan_cooling": FanCooling,
    "holding_brake": HoldingBrake,
    "driver_conduction": DriverConduction,
    "decoy_channels": DecoyChannels,
}
# effects that log a channel of their own (and need the plant's generator for their schedules)
SCHEDULED = ("fan_cooling", "holding_brake", "driver_conduction", "decoy_channels")
