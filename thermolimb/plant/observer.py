"""Estimate the winding temperature a thermistor cannot show, and the time left before it reaches its limit.

A thermistor sits on the winding's outside and lags it; at high current the
winding can be several kelvin hotter than it reads.  Firmware protects the
winding it cannot measure with a model, and so does this module: a Kalman
filter per actuator on its thermal network (winding, housing, body), the
thermistor's lag, and the heat it does not know: losses growing with speed
(``c1 |v| + c2 v^2``, iron and friction, their coefficients learned online)
and an unknown extra heat in the winding (a random walk: a drifting ambient,
a neighbour's heat).  The heat it knows is the measured current through the
copper's resistance, which rises 0.39 %/K.

:class:`WindingObserver` runs online, from current, measured temperature and
ambient at each control step (the plant's thermal protection runs one).  A
logged run with an identified model is watched by the monitor's estimator
(:class:`~thermolimb.monitor.ActuatorMonitor`), which answers the time to a
limit and the status by the same rules (:mod:`thermolimb.model.reach`).
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from ..constants import COPPER_REFERENCE_C, COPPER_TEMPCO_PER_K
from ..model.reach import crossing_s
from .zoh import zero_order_hold


class WindingObserver:
    """A Kalman filter per actuator: network nodes, the thermistor, and an unknown winding heat (W).

    Parameters
    ----------
    specs
        One :class:`~thermolimb.plant.ActuatorSpec` per actuator (its network and winding resistance).
    sensor_tau_s
        The thermistor's time constant (s), or ``None`` when it reads the winding directly.
    initial_C
        Every node's temperature at the start (degC), per actuator or one for all.
    measurement_std_K
        The thermistor's noise (1 sigma, K), quantisation included.
    heat_walk_W
        How fast the unknown heat may change: its standard deviation grows by this per square-root hour.
    copper_alpha_per_K
        The winding resistance's temperature coefficient (copper: 0.0039/K).
    """

    def __init__(self, specs: Sequence, sensor_tau_s: float | None = None, initial_C=25.0,
                 measurement_std_K: float = 0.1, heat_walk_W: float = 100.0,
                 copper_alpha_per_K: float = COPPER_TEMPCO_PER_K):
        if sensor_tau_s is not None and not sensor_tau_s > 0:
            raise ValueError(f"sensor_tau_s must be positive or None, got {sensor_tau_s}")
        if not measurement_std_K > 0:
            raise ValueError(f"measurement_std_K must be positive, got {measurement_std_K}")
        self.m = len(specs)
        self.nodes = max(s.network.n_nodes for s in specs)
        self.sensor = self.nodes if sensor_tau_s is not None else 0  # the measured state
        self.heat = self.nodes + (1 if sensor_tau_s is not None else 0)  # the unknown heat state (W)
        self.speed = self.heat + 1  # two states: speed-loss coefficients, W per rad/s and W per (rad/s)^2
        n = self.heat + 3
        self.n = n
        self.alpha = copper_alpha_per_K
        self.resistance_ohm = np.array([s.winding_resistance_ohm for s in specs])
        self.r_meas = measurement_std_K**2
        self.q_heat = (heat_walk_W**2) / 3600.0  # W^2 per s
        self.q_speed = np.array([0.5, 0.5]) ** 2 / 3600.0  # the loss coefficients drift slowly
        self._A = np.zeros((self.m, n, n))
        self._B = np.zeros((self.m, n, 2))  # inputs: known winding heat (W), ambient (degC)
        for i, spec in enumerate(specs):
            net = spec.network
            k = net.n_nodes
            A = self._A[i]
            A[:k, :k] = net.system_matrix()
            for pad in range(k, self.nodes):  # unused nodes of a shorter network: isolated, decaying
                A[pad, pad] = -1.0
            C = np.asarray(net.capacity_J_per_K)
            A[0, self.heat] = 1.0 / C[0]
            self._B[i, 0, 0] = 1.0 / C[0]
            self._B[i, k - 1, 1] = 1.0 / (net.resistance_K_per_W[-1] * C[-1])
            if sensor_tau_s is not None:
                A[self.sensor, 0] = 1.0 / sensor_tau_s
                A[self.sensor, self.sensor] = -1.0 / sensor_tau_s
        self._cache: dict[float, tuple[np.ndarray, np.ndarray, np.ndarray]] = {}
        self._last_speed = (None, None)
        self.reset(initial_C)

    def reset(self, temperature_C) -> None:
        """Every node (and the thermistor) at ``temperature_C`` (per actuator or one), no unknown heat."""
        T = np.broadcast_to(np.asarray(temperature_C, float), (self.m,))
        self.x = np.zeros((self.m, self.n))
        self.x[:, : self.heat] = T[:, None]
        self.P = np.zeros((self.m, self.n, self.n))
        self.P[:, np.arange(self.heat), np.arange(self.heat)] = 1.0  # 1 K at the start
        self.P[:, self.heat, self.heat] = 1.0
        self.P[:, self.speed, self.speed] = 1.0
        self.P[:, self.speed + 1, self.speed + 1] = 0.25

    def _discrete(self, dt_s: float):
        if dt_s not in self._cache:
            n = self.n
            Phi, Gam = np.empty((self.m, n, n)), np.empty((self.m, n, 2))
            Qd = np.zeros((self.m, n, n))
            for i in range(self.m):
                Phi[i], Gam[i] = zero_order_hold(self._A[i], self._B[i], dt_s)
                # the unknown heat's and the loss coefficients' random walks (first order in dt)
                g = Phi[i][:, self.heat]
                Qd[i] = np.outer(g, g) * self.q_heat * dt_s
                Qd[i, self.speed, self.speed] = self.q_speed[0] * dt_s
                Qd[i, self.speed + 1, self.speed + 1] = self.q_speed[1] * dt_s
                Phi[i][self.speed :, self.speed :] = np.eye(2)
            self._cache[dt_s] = (Phi, Gam, Qd)
        return self._cache[dt_s]

    def known_heat_W(self, current_A: np.ndarray, winding_C: np.ndarray | None = None) -> np.ndarray:
        """Copper loss of the measured current at the estimated winding temperature (or at ``winding_C``)."""
        winding = self.x[:, 0] if winding_C is None else winding_C
        return np.asarray(current_A, float) ** 2 * self.resistance_ohm * (
            1.0 + self.alpha * (winding - COPPER_REFERENCE_C))

    def speed_transitions(self, Phi: np.ndarray, speed_rad_s: np.ndarray) -> np.ndarray:
        """The transition with each interval's speed losses: unit heat's response times each feature, for
        speeds of shape ``(..., m)`` (one interval, or a block of them)."""
        v = np.abs(np.asarray(speed_rad_s, float))
        out = np.broadcast_to(Phi, v.shape[:-1] + Phi.shape).copy()
        g = Phi[:, : self.heat, self.heat]
        out[..., : self.heat, self.speed] = g * v[..., None]
        out[..., : self.heat, self.speed + 1] = g * (v**2)[..., None]
        return out

    def _with_speed(self, Phi: np.ndarray, speed_rad_s) -> np.ndarray:
        """:meth:`speed_transitions` of one interval, kept while the speed is unchanged."""
        if speed_rad_s is None:
            return Phi
        v = np.broadcast_to(np.asarray(speed_rad_s, float), (self.m,))
        key = (id(Phi), v.tobytes())
        if self._last_speed[0] != key:  # the plant asks twice per interval (cap, then update)
            self._last_speed = (key, self.speed_transitions(Phi, v))
        return self._last_speed[1]

    def _predict(
        self, Phi: np.ndarray, Gam: np.ndarray, Qd: np.ndarray, heat_W: np.ndarray, ambient_C: float
    ):
        self.x = (
            (Phi @ self.x[:, :, None])[:, :, 0] + Gam[:, :, 0] * heat_W[:, None] + Gam[:, :, 1] * ambient_C
        )
        self.P = Phi @ self.P @ Phi.transpose(0, 2, 1) + Qd

    def _correct(self, measured_C: np.ndarray):
        s = self.sensor
        column = self.P[:, :, s]
        gain = column / (column[:, s] + self.r_meas)[:, None]
        self.x += gain * (measured_C - self.x[:, s])[:, None]
        self.P -= gain[:, :, None] * column[:, None, :]  # P is symmetric: its row s is its column s

    def predict(self, current_A: np.ndarray, ambient_C: float, dt_s: float,
                speed_rad_s: np.ndarray | None = None) -> np.ndarray:
        """Advance the estimate over an interval of ``dt_s`` with ``current_A`` (and ``speed_rad_s``) held."""
        Phi, Gam, Qd = self._discrete(float(dt_s))
        self._predict(self._with_speed(Phi, speed_rad_s), Gam, Qd, self.known_heat_W(current_A),
                      float(ambient_C))
        return self.winding_C

    def update(self, current_A: np.ndarray, measured_C: np.ndarray, ambient_C: float, dt_s: float,
               speed_rad_s: np.ndarray | None = None) -> np.ndarray:
        """Predict over an interval of ``dt_s`` with ``current_A`` (and ``speed_rad_s``) held, then correct
        with the reading at its end."""
        self.predict(current_A, ambient_C, dt_s, speed_rad_s)
        self._correct(np.asarray(measured_C, float))
        return self.winding_C

    def run(self, current_A: np.ndarray, measured_C: np.ndarray, ambient_C: np.ndarray, dt_s: float,
            speed_rad_s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """:meth:`update` over a block of intervals (rows of ``current_A``, ``measured_C``, ``ambient_C``,
        ``speed_rad_s``), with a copper coefficient of 0 (the heat does not depend on the estimate).  Returns
        every state, covariance and transition, the first row the state before the block, the last after
        it."""
        if self.alpha != 0.0:
            raise ValueError("WindingObserver.run needs copper_alpha_per_K = 0; step with update() otherwise")
        Phi, Gam, Qd = self._discrete(float(dt_s))
        Phis = self.speed_transitions(Phi, speed_rad_s)
        # the coefficient is 0: any winding temperature
        heat = self.known_heat_W(current_A, COPPER_REFERENCE_C)
        states, covariances = [self.x.copy()], [self.P.copy()]
        for k in range(len(heat)):
            self._predict(Phis[k], Gam, Qd, heat[k], float(ambient_C[k]))
            self._correct(measured_C[k])
            states.append(self.x.copy())
            covariances.append(self.P.copy())
        return np.array(states), np.array(covariances), Phis

    def set_state(self, x: np.ndarray, P: np.ndarray) -> None:
        """Put the filter at a state and covariance :meth:`run` returned (a block taken only in part)."""
        self.x, self.P = x.copy(), P.copy()

    def fraction_cap(self, x: np.ndarray, Phi_v: np.ndarray, current_A: np.ndarray, limit_C, ambient_C,
                     dt_s: float) -> np.ndarray:
        """:meth:`current_fraction_cap` from states ``x`` and speed transitions ``Phi_v`` of shape ``(..., m,
        n)`` and ``(..., m, n, n)`` (one interval, or a block of them)."""
        _, Gam, _ = self._discrete(float(dt_s))
        ambient = np.asarray(ambient_C, float)[..., None] if np.ndim(ambient_C) else float(ambient_C)
        free = (Phi_v[..., 0, :] * x).sum(axis=-1) + Gam[:, 0, 1] * ambient
        full = Gam[:, 0, 0] * self.known_heat_W(current_A, x[..., 0])
        room = limit_C - free
        share = (room >= 0.0).astype(float)
        heating = full > 0.0
        share[heating] = np.sqrt(np.clip(room[heating] / full[heating], 0.0, 1.0))
        return share

    def current_fraction_cap(self, current_A: np.ndarray, limit_C, ambient_C: float, dt_s: float,
                             speed_rad_s=None) -> np.ndarray:
        """The largest share of ``current_A`` (0 to 1) that keeps the predicted winding at or below
        ``limit_C`` at the end of the next ``dt_s`` (heat grows with the share squared); 0 where even no
        current overshoots."""
        Phi, _, _ = self._discrete(float(dt_s))
        return self.fraction_cap(self.x, self._with_speed(Phi, speed_rad_s), current_A, limit_C, ambient_C,
                                 dt_s)

    @property
    def winding_C(self) -> np.ndarray:
        return self.x[:, 0].copy()

    @property
    def winding_std_K(self) -> np.ndarray:
        return np.sqrt(np.maximum(self.P[:, 0, 0], 0.0))

    def time_to_limit_s(self, current_A: np.ndarray, limit_C, ambient_C: float, speed_rad_s=None,
                        horizon_s: float = 4 * 3600.0, step_s: float = 10.0) -> list[float | None]:
        """Time until each estimated winding reaches ``limit_C`` if ``current_A``, the speed and the unknown
        heat were held: the network simulated ahead every ``step_s`` and its first crossing
        (:func:`~thermolimb.model.reach.crossing_s`); ``None`` when not within ``horizon_s``."""
        limit = np.broadcast_to(np.asarray(limit_C, float), (self.m,))
        Phi, Gam, _ = self._discrete(float(step_s))
        Phi = self._with_speed(Phi, speed_rad_s)
        x = self.x.copy()
        winding = [x[:, 0]]
        reached = x[:, 0] >= limit
        for _ in range(int(horizon_s / step_s)):
            if reached.all():
                break
            heat = np.asarray(current_A, float) ** 2 * self.resistance_ohm * (
                1.0 + self.alpha * (x[:, 0] - COPPER_REFERENCE_C))
            u = np.stack([heat, np.full(self.m, float(ambient_C))], axis=1)
            x = np.einsum("mij,mj->mi", Phi, x) + np.einsum("mij,mj->mi", Gam, u)
            winding.append(x[:, 0])
            reached |= x[:, 0] >= limit
        curves = np.array(winding)
        times = step_s * np.arange(len(curves))
        return [crossing_s(times, curves[:, i], limit[i]) for i in range(self.m)]
