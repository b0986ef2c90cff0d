"""The monitor's estimate for each actuator, one piece of the log at a time: the winding temperature, the time
left before its limit at the current effort, and the protection's derating.

For each actuator the identified model (a :class:`~thermolimb.model.saved.SavedModel`) runs free over the
log's inputs, carried exactly from piece to piece (:meth:`ThermalModel.simulate`'s ``state``), and a Kalman
filter corrects it with each reading.  What the filter estimates is the model's error: a disturbance ``b`` on
the winding that the winding forgets with its own time constant (``b' = a b + w``, ``a = exp(-dt / RC)``),
read through the sensor (``y = model output + b + v``).  This is the plant's winding observer
(:class:`~thermolimb.plant.observer.WindingObserver`) on the identified model instead of the plant's network:
the model supplies the physics, the readings hold it to the robot.  The process noise is set from the model
file's held-out residual (its RMSE is the size of what the model misses), the measurement noise from the log's
resolution.  The estimate's standard deviation adds to the filter's the uncertainty of a lagging sensor's time
constant times the temperature's rate of change (how far ahead of the reading the winding runs).

The forecast holds the current inputs: the model's steady state under them (its forcing ``u``) and its rate
``lam`` give ``t = ln((T - u) / (L - u)) / lam`` from the estimate ``T`` to the limit ``L``; with slow masses,
whose share of the rise builds up later, this is the soonest the winding can get there.  The derating is
:class:`~thermolimb.plant.protection.ThermalProtection`'s on the estimate plus two standard deviations.

A run whose first piece logs an ambient beyond the model file's calibration moves the model's offset with it,
as ``predict`` and held-out runs do (:func:`~thermolimb.model.experience.ambient_shift_K`); ``note`` says so.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model.arrays import ModelArrays, steps_together
from ..model.experience import EQ5, shifted
from ..model.reach import first_order_reach_s
from ..model.saved import SavedModel
from ..model.signals import Signals
from ..plant.protection import ThermalProtection

OK, WARN, ERROR = 0, 1, 2
LEVELS = {OK: "OK", WARN: "WARN", ERROR: "ERROR"}
WARN_WITHIN_S = 120.0  # WARN when the forecast reaches the limit sooner than this
DEFAULT_MEASUREMENT_STD_K = 0.1


def level(winding_C: float, limit_C: float, derating: float, time_to_limit_s: float | None) -> int:
    """The status rule, for the monitor and the rig's live view alike: ERROR at or above the limit; WARN while
    protection derates or the limit is less than :data:`WARN_WITHIN_S` away; else OK."""
    if winding_C >= limit_C:
        return ERROR
    soon = time_to_limit_s is not None and time_to_limit_s < WARN_WITHIN_S
    return WARN if derating < 1.0 or soon else OK


@dataclass(frozen=True)
class Estimate:
    """One actuator's state after a piece of log, at its last sample."""

    actuator: str
    time_s: float
    measured_C: float
    winding_C: float
    winding_std_K: float
    time_to_limit_s: float | None  # None: never at the current effort
    derating: float  # the share of effort protection allows (1: none taken)
    level: int  # OK, WARN, ERROR
    limit_C: float

    @property
    def status(self) -> str:
        return LEVELS[self.level]

    def message(self) -> str:
        if self.level == ERROR:
            return f"winding at {self.winding_C:.1f} degC, at or above its {self.limit_C:g} degC limit"
        ttl = "not at this effort" if self.time_to_limit_s is None else f"in {self.time_to_limit_s:.0f} s"
        return f"winding {self.winding_C:.1f} degC; reaches {self.limit_C:g} degC {ttl}"

    def to_json(self) -> dict:
        return {"actuator": self.actuator, "time_s": self.time_s, "measured_C": self.measured_C,
                "winding_C": self.winding_C, "winding_std_K": self.winding_std_K,
                "time_to_limit_s": self.time_to_limit_s, "derating": self.derating, "status": self.status,
                "limit_C": self.limit_C}


class ActuatorMonitor:
    """One actuator's model state and filter, fed piece by piece (each piece starts at the last one's end)."""

    def __init__(
        self,
        saved: SavedModel,
        limit_C: float,
        measurement_std_K: float = DEFAULT_MEASUREMENT_STD_K,
        protection: ThermalProtection = ThermalProtection(),
        sigmas: float = 2.0,
    ):
        if not np.isfinite(limit_C):
            raise ValueError(f"the limit of {saved.actuator} must be a finite degC, got {limit_C}")
        self.saved = saved
        self.model = saved.model
        self.limit_C = float(limit_C)
        self.protection = protection
        self.sigmas = sigmas
        self.r = measurement_std_K**2
        miss = saved.residual.rmse_K if saved.residual is not None else 0.5
        # the disturbance's stationary spread is the model's held-out error: q = miss^2 (1 - a^2) per step
        self.miss_K = max(miss, measurement_std_K)
        # a lagging sensor's time constant is uncertain: the winding's distance ahead of the reading, tau
        # dT/dt, is uncertain by sigma_tau |dT/dt| (the jackknife's spread when the file has it)
        names = [p.name for p in saved.model.parameters]
        spread = saved.jackknife if saved.jackknife is not None else saved.covariance
        self.sigma_tau_s = (
            float(np.sqrt(max(spread[names.index("sensor_tau_s")][names.index("sensor_tau_s")], 0.0)))
            if "sensor_tau_s" in names
            else 0.0
        )
        self.together = steps_together(self.model)  # can step with others (update_together)
        self.row = ModelArrays.row(self.model) if self.together else None
        self.columns = self.model.columns
        self.state: dict | None = None
        self.bias = 0.0
        self.P = self.miss_K**2
        self.last: Estimate | None = None
        self.note = ""  # what the first piece said of the model (its offset following another air)

    def update(self, signals: Signals, measured_C: np.ndarray) -> Estimate:
        """Advance over ``signals`` (its first sample is the previous piece's last, except on the first
        piece)."""
        keep: dict = {}
        first = self.state is None
        if first:
            self._follow_ambient(signals)
        sim = self.model.simulate(signals, float(measured_C[0]), state=self.state, keep=keep)
        self.state = keep
        decay = np.exp(-np.diff(signals.time_s) / self.model.params["RC_s"]).tolist()
        innovation = (np.asarray(measured_C, float) - sim).tolist()
        bias, P = (0.0, self.r) if first else (self.bias, self.P)
        for k in range(0 if first else 1, signals.n):
            bias, P = _correct(bias, P, decay[k - 1] if k > 0 else 1.0, self.miss_K**2, self.r, innovation[k])
        self.bias, self.P = bias, P
        winding = keep["winding"] + bias  # the model's winding, less what the readings say it misses
        slope = (sim[-1] - sim[-2]) / (signals.time_s[-1] - signals.time_s[-2]) if signals.n > 1 else 0.0
        std = float(np.sqrt(self.P + (self.sigma_tau_s * slope) ** 2))
        ttl = first_order_reach_s(winding, keep["steady_C"], keep["rate_per_s"], self.limit_C)
        derate = float(
            self.protection.fraction(np.array([winding + self.sigmas * std]), np.array([self.limit_C]))[0]
        )
        self.last = Estimate(self.saved.actuator, float(signals.time_s[-1]), float(measured_C[-1]),
                             float(winding), std, ttl, derate, level(winding, self.limit_C, derate, ttl),
                             self.limit_C)
        return self.last

    def _follow_ambient(self, signals: Signals) -> None:
        air, shift = self.saved.offset_air_C, self.saved.offset_shift_K(signals.ambient_C)
        if not shift:
            return
        self.model = shifted(self.saved.model, shift)
        self.row = ModelArrays.row(self.model) if self.together else None
        self.note = (f"{self.saved.actuator}: the ambient here lies "
                     f"beyond the {air[0]:.1f} to {air[1]:.1f} degC the "
                     f"model's offset stands for; its offset follows it, {shift:+.1f} K ({EQ5})")


def _correct(bias, P, a, q, r, innovation):
    """The filter over one interval (scalars, or arrays of actuators): the disturbance ``bias`` decays with
    the winding (``a``) as its variance ``P`` gains ``q (1 - a^2)``; then the reading's ``innovation``
    corrects it."""
    P = a * a * P + q * (1.0 - a * a)
    gain = P / (P + r)
    return bias * a + gain * (innovation - bias * a), P * (1.0 - gain)


def update_together(monitors: list[ActuatorMonitor], arrays: list[dict]) -> list[Estimate]:
    """One new sample for each of several actuators at once: each monitor ``together`` (a model that
    :mod:`~thermolimb.model.arrays` steps) with its filter already running, sharing one protection; each
    ``arrays`` the previous sample and the new one, with every column its model reads.  The same numbers as
    each monitor's :meth:`~ActuatorMonitor.update` (what a live log polled after every row asks thirty times a
    millisecond), as arrays."""
    first = monitors[0]
    models = ModelArrays(rows=np.array([m.row for m in monitors]))
    time_s = np.array([a["time"] for a in arrays])
    effort = np.array([a["effort"] for a in arrays])
    speed = np.abs(np.array([a["velocity"] if "velocity" in a else np.zeros(2) for a in arrays]))
    measured = np.array([a["temperature"][1] for a in arrays])
    dt = time_s[:, 1] - time_s[:, 0]
    before = {k: np.array([m.state.get(k, np.nan) for m in monitors]) for k in ("winding", "output")}
    for name in models.stage_names:
        before[name] = np.array([m.state.get(name, o) for m, o in zip(monitors, models.offset)])
    after = models.step(before, dt, effort, speed)
    bias, P = _correct(np.array([m.bias for m in monitors]), np.array([m.P for m in monitors]),
                       np.exp(-dt / models.rc), np.array([m.miss_K**2 for m in monitors]),
                       np.array([m.r for m in monitors]), measured - after["output"])
    winding = after["winding"] + bias
    slope = (after["output"] - before["output"]) / dt
    std = np.sqrt(P + (np.array([m.sigma_tau_s for m in monitors]) * slope) ** 2)
    limit = np.array([m.limit_C for m in monitors])
    derate = first.protection.fraction(winding + first.sigmas * std, limit)
    estimates = []
    for k, m in enumerate(monitors):
        # the keys the model's own run keeps: a slow mass carries its node only where it has a share
        m.state = {key: float(after[key][k]) for key in m.state}
        m.bias, m.P = float(bias[k]), float(P[k])
        w = float(winding[k])
        ttl = first_order_reach_s(w, float(after["steady_C"][k]), float(after["rate_per_s"][k]), m.limit_C)
        m.last = Estimate(m.saved.actuator, float(time_s[k, 1]), float(measured[k]), w, float(std[k]), ttl,
                          float(derate[k]), level(w, m.limit_C, float(derate[k]), ttl), m.limit_C)
        estimates.append(m.last)
    return estimates
