"""A thermistor that lags the winding: it reads a first-order lag of the winding's temperature."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model.scan import first_order_scan
from ..model.terms import Parameter, Term, register_term
from .base import ONSETS, Effect, Hidden, PlantEffect, register


@register_term
class SensorLagTerm(Term):
    """The thermistor lags the winding: ``tau_s dT_s/dt = T - T_s``."""

    name = "sensor_lag"
    lags_output = True
    label = "sensor lag"
    description = "the thermistor lags the winding"
    parameters = (
        Parameter("sensor_tau_s", "s", 0.0, 600.0, 10.0, "time constant of the thermistor",
                  "fast temperature changes (short heating bursts)", plausible=(0.2, 120.0)),
    )

    def output_lag_s(self, p):
        return p["sensor_tau_s"]

    def initial_winding(self, p, measured_C, rate_K_per_s):
        return measured_C + p["sensor_tau_s"] * rate_K_per_s  # the lagged reading trails the winding

    def shape_output(self, p, s, winding_C, measured_initial_C):
        tau = p["sensor_tau_s"]
        if tau <= 0.0:
            return winding_C
        dt = s.interval_s
        a = np.exp(-dt / tau)
        # first-order hold: exact when the winding temperature moves linearly between samples
        ramp = 1.0 - tau / dt * (1.0 - a)
        b = (1.0 - a) * winding_C[:-1] + ramp * np.diff(winding_C)
        return first_order_scan(a, b, measured_initial_C)


@dataclass(frozen=True)
class SensorLag(PlantEffect):
    """The thermistor follows the winding with a first-order lag."""

    name = "sensor_lag"
    sensor_node = True
    time_constant_s: float = 15.0

    def wire(self, net):
        rate = 1.0 / self.time_constant_s
        net.A[net.sensor, net.sensor] = -rate
        net.A[net.sensor, net.winding] = rate


register(
    Effect("sensor_lag", SensorLagTerm, SensorLag, residual=ONSETS, hidden=Hidden("sensor_lag", "sensor_lag"))
)
