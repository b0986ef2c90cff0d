"""The thermal plant: the rig's "hardware" that heats every simulated actuator.

Each actuator is a chain of thermal masses (winding, housing, body by default,
HEBI X8 numbers) heated by the motor current, optionally with a driver board
node and a thermistor node.  The whole plant is one linear network

    dx/dt = A x + B q + b_amb T_amb

integrated *exactly* for inputs held over each control interval (zero-order
hold through the matrix exponential), so it is stable at any control rate.
Effects whose heat depends on the state (copper resistance, motion cooling)
enter through ``q`` evaluated at the start of each interval.  Each effect that is
on acts through its hooks (:class:`~thermolimb.effects.PlantEffect`): the plant
iterates them and names none.
"""

from __future__ import annotations

from types import SimpleNamespace
from typing import Sequence

import numpy as np

from ..effects import PlantEffects
from ..util.errors import check_range
from .network import ActuatorSpec, Layout
from .protection import ThermalProtection, scale_efforts
from .schedules import ScheduledChannel
from .sensors import Thermistors
from .zoh import zero_order_hold

AMBIENT_RANGE_C = (-60.0, 150.0)
TEMPERATURE_RANGE_C = (-60.0, 400.0)  # what a winding, a housing or a sensor may be set to (degC)


class ThermalPlant:
    """Thermal state of named actuators, advanced one control interval at a time.

    Parameters
    ----------
    names, specs
        One name and one :class:`ActuatorSpec` per actuator; neighbours (for
        neighbour conduction) are consecutive names.
    effects
        Which effects are on (:class:`PlantEffects`).
    ambient_C
        Ambient temperature at time 0 (degC).
    initial_C
        Initial temperature of every node (degC); ambient if ``None``.
    rng
        Generator for sensor noise; required when noise is on.
    """

    def __init__(
        self,
        names: Sequence[str],
        specs: Sequence[ActuatorSpec],
        effects: PlantEffects = PlantEffects(),
        ambient_C: float = 25.0,
        initial_C: float | None = None,
        rng: np.random.Generator | None = None,
        protection: ThermalProtection = ThermalProtection(),
    ):
        if len(names) != len(specs) or len(names) == 0:
            raise ValueError("ThermalPlant needs one spec per actuator name, "
                             f"got {len(names)} names and {len(specs)} specs")
        if len(set(names)) != len(names):
            raise ValueError(f"actuator names must be unique, got {list(names)}")
        random = [fx.name for fx in effects.active if fx.draws_random]
        if random and rng is None:
            raise ValueError(f"{', '.join(random)} {'is' if len(random) == 1 else 'are'} "
                             "on and draw random numbers: "
                             f"pass rng=np.random.default_rng(seed)")
        for fx in effects.active:
            fx.check(specs)
        check_range("ThermalPlant", "ambient_C", ambient_C, AMBIENT_RANGE_C[0], AMBIENT_RANGE_C[1], "degC")
        if initial_C is not None:
            check_range("ThermalPlant", "initial_C", initial_C, *TEMPERATURE_RANGE_C, "degC")
        self.names = tuple(names)
        self.specs = tuple(specs)
        self.effects = effects
        self.ambient0_C = float(ambient_C)
        self.protection = protection
        self.winding_limits_C = np.array([spec.winding_limit_C for spec in self.specs])
        self.observer = None
        self._applied_fraction = np.ones(len(self.specs))  # the share of current protection allowed last
        self._rng = rng  # the schedules' draws (the sensors draw their noise from the same generator)
        self.sensors = Thermistors(effects, rng)
        self.layout = Layout.build(self.specs, effects)
        self._n_states = self.layout.n_states
        self._effort_per_amp = np.array([s.effort_per_amp for s in self.specs])
        self._resistance_ohm = np.array([s.winding_resistance_ohm for s in self.specs])
        self._driver_ohm = np.array([s.driver.loss_resistance_ohm if s.driver else 0.0 for s in self.specs])
        self._has_driver = self.layout.driver >= 0
        self._schedules = self._make_schedules()
        self.time_s = 0.0
        start = self.ambient0_C if initial_C is None else float(initial_C)
        self._x = np.full(self._n_states, start)
        self._discretised: dict[float, tuple[np.ndarray, np.ndarray]] = {}
        self.current_A = np.zeros(self.n)
        # N m or N: what a drive holds at most
        self.peak_effort = np.array([spec.effort_limit for spec in self.specs])
        # a non-finite command faulted the actuator (cleared by clear_faults)
        self.faulted = np.zeros(self.n, bool)
        self.saturations = np.zeros(self.n, int)  # steps whose effort was held at the actuator's peak
        self._measure()
        if protection.estimator == "observer":
            self.observer = self.sensors.observer(self.specs, start)

    # ----------------------------------------------------------------- layout
    @property
    def n(self) -> int:
        return len(self.names)

    def _make_schedules(self) -> dict[str, ScheduledChannel]:
        """The random schedules of the effects that log a channel, from one generator drawn off the
        plant's."""
        plans = [(key, schedule) for fx in self.effects.active for key, schedule in fx.schedules().items()]
        if not plans:
            return {}
        rng = np.random.default_rng(self._rng.integers(2**63))
        return {key: ScheduledChannel(schedule, self.n, rng) for key, schedule in plans}

    def schedule(self, key: str) -> np.ndarray:
        """Each actuator's level of the schedule ``key`` (a fan's duty, a brake's state) now."""
        return self._schedules[key].at(self.time_s)

    def logged_channels(self) -> dict[str, np.ndarray]:
        """The extra channels the switched-on effects log, by column name (unit in the name), per actuator,
        now."""
        return {column: values for fx in self.effects.active for column, values in fx.logged(self).items()}

    def _discretisation(self, dt_s: float) -> tuple[np.ndarray, np.ndarray]:
        """Exact ZOH matrices ``(Phi, Gamma)`` with ``x+ = Phi x + Gamma [q; T_amb]``."""
        key = round(dt_s, 12)
        if key not in self._discretised:
            inputs = np.column_stack([np.diag(self.layout.inv_capacity), self.layout.b_amb])
            self._discretised[key] = zero_order_hold(self.layout.A, inputs, dt_s)
        return self._discretised[key]

    # ----------------------------------------------------------------- inputs
    def ambient_at(self, time_s: float) -> float:
        """Ambient temperature (degC) at ``time_s``."""
        for fx in self.effects.active:
            moved = fx.ambient_C(self.ambient0_C, time_s)
            if moved is not None:
                return moved
        return self.ambient0_C

    def _current_sq(self, effort: np.ndarray, speed: np.ndarray, field_share) -> np.ndarray:
        """Squared motor current (A^2): torque current from the effort (less what the effects leave out of it,
        a series-elastic bias) and current that makes no torque (field weakening above a base speed), the
        latter scaled by ``field_share``."""
        torque_effort, i_d = effort, 0.0
        for fx in self.effects.active:
            torque_effort = fx.torque_effort(torque_effort)
            i_d = i_d + fx.extra_current_A(speed, field_share)
        i_q = torque_effort / self._effort_per_amp
        return i_q**2 + i_d**2

    def heat_W(self, effort: np.ndarray, velocity: np.ndarray) -> np.ndarray:
        """Heat into every state node (W) for efforts and velocities held over the next interval.

        Also updates :attr:`current_A`, the motor current magnitude.
        """
        constant, per_kelvin = self.heat_affine(effort, velocity)
        return constant + per_kelvin * self._x

    def heat_affine(self, effort: np.ndarray, velocity: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The heat into every state node as ``constant + per_kelvin * x`` (W and W/K, per node) for the state
        ``x``.

        Every effect whose heat depends on the state does so linearly and
        node by node (copper resistance on the winding, motion cooling on the
        outer node), which keeps the plant a linear network for held inputs.
        Also updates :attr:`current_A`.
        """
        net = self.layout
        speed = np.abs(np.asarray(velocity, dtype=float))
        current_sq = self._current_sq(np.asarray(effort, dtype=float), speed, self._applied_fraction)
        self.current_A = np.sqrt(current_sq)
        shape = current_sq.shape[:-1] + (self._n_states,)  # one interval, or a block of them (free_block)
        constant = np.zeros(shape)
        per_kelvin = np.zeros(shape)
        joule = current_sq * self._resistance_ohm
        if not any([fx.place_joule(net, joule, constant, per_kelvin) for fx in self.effects.active]):
            constant[..., net.winding] += joule
        constant[..., net.driver[self._has_driver]] += (current_sq * self._driver_ohm)[..., self._has_driver]
        at = SimpleNamespace(speed=speed, time_s=self.time_s, ambient_C=self.ambient_at(self.time_s),
                             schedules=self._schedules)
        for fx in self.effects.active:
            fx.heat(net, at, constant, per_kelvin)
        return constant, per_kelvin

    def set_temperatures(self, temperature_C: np.ndarray, rest_C: np.ndarray | None = None) -> None:
        """Put each actuator's winding and sensor at ``temperature_C`` (degC) and its other nodes (housing,
        body, driver) at ``rest_C`` (default the same: an actuator soaked through).  A winding heated for a
        minute or two sits on a housing that has barely warmed: give ``rest_C`` near ambient for that."""
        temperature_C = self._per_actuator("temperature_C", temperature_C)
        rest_C = temperature_C if rest_C is None else self._per_actuator("rest_C", rest_C)
        net = self.layout
        for i in range(self.n):
            nodes = net.winding[i] + np.arange(self.specs[i].network.n_nodes)
            self._x[nodes] = rest_C[i]
            self._x[net.winding[i]] = temperature_C[i]
            self._x[net.sensor[i]] = temperature_C[i]
            if net.driver[i] >= 0:
                self._x[net.driver[i]] = rest_C[i]
        self._measure()
        if self.observer is not None:
            self.observer.reset(temperature_C)

    def _per_actuator(self, name: str, value) -> np.ndarray:
        """One temperature for every actuator, or one per actuator -- not a list of another length -- each
        within :data:`TEMPERATURE_RANGE_C`."""
        arr = np.asarray(value, float)
        if arr.ndim > 1 or (arr.ndim == 1 and arr.shape[0] != self.n):
            raise ValueError(f"set_temperatures: {name} needs one temperature or {self.n} (one per actuator: "
                             f"{', '.join(self.names)}), got {arr.shape[0] if arr.ndim == 1 else arr.shape}")
        arr = np.broadcast_to(arr, (self.n,))
        bad = [i for i in range(self.n) if not TEMPERATURE_RANGE_C[0] <= arr[i] <= TEMPERATURE_RANGE_C[1]]
        if bad:
            raise ValueError(f"set_temperatures: {name} of {self.names[bad[0]]} "
                             f"= {float(arr[bad[0]])!r} is outside the range "
                             f"expected, {TEMPERATURE_RANGE_C[0]:g} to {TEMPERATURE_RANGE_C[1]:g} degC")
        return arr

    @property
    def state(self) -> np.ndarray:
        """Every node's true temperature (degC): the state vector a
        :class:`~thermolimb.plant.periodic.CycleMap` maps."""
        return self._x.copy()

    def set_state(self, state: np.ndarray) -> None:
        """Put the network in a state read from :attr:`state` (degC); sensors read it, the observer starts
        from it."""
        state = np.asarray(state, float)
        if state.shape != self._x.shape or not np.all(np.isfinite(state)):
            raise ValueError(f"a plant state needs {self._x.shape[0]} "
                             f"finite temperatures, got shape {state.shape}")
        self._x = state.copy()
        self._measure()
        if self.observer is not None:
            self.observer.reset(self._x[self.layout.winding])

    # ------------------------------------------------------------------ steps
    def step(self, effort: np.ndarray, velocity: np.ndarray | None, dt_s: float) -> None:
        """Advance by ``dt_s`` seconds with efforts (N m or N) and velocities held.

        As a drive does: an effort beyond an actuator's peak is held at the peak (and counted in
        :attr:`saturations`); a command that is not a finite number faults that actuator -- no torque, a flag
        in :attr:`faulted` until :meth:`clear_faults` -- instead of poisoning the state."""
        if not (np.isfinite(dt_s) and dt_s > 0):
            raise ValueError(f"dt_s must be a positive, finite number of seconds, got {dt_s}")
        effort, velocity = self.commanded(effort, velocity)
        q = self.heat_W(effort, velocity)
        Phi, Gamma = self._discretisation(dt_s)
        ambient = self.ambient_at(self.time_s)
        self._x = Phi @ self._x + Gamma @ np.append(q, ambient)
        self.time_s += dt_s
        self._measure()
        if self.observer is not None:
            self.observer.update(self.current_A, self._measured_core, ambient, dt_s, velocity)

    def commanded(self, effort, velocity) -> tuple[np.ndarray, np.ndarray]:
        """What the drives make of a command: non-finite values fault their actuator (zero effort and speed
        from then on), efforts beyond the peak are saturated at it and counted."""
        effort, velocity = self._each("effort", effort), np.zeros(self.n) if velocity is None else \
            self._each("velocity", velocity)
        self.faulted |= ~(np.isfinite(effort) & np.isfinite(velocity))
        effort[self.faulted] = 0.0
        velocity[self.faulted] = 0.0
        over = np.abs(effort) > self.peak_effort
        self.saturations += over
        return np.clip(effort, -self.peak_effort, self.peak_effort), velocity

    def _each(self, name: str, value) -> np.ndarray:
        """One value per actuator (a single number is every actuator's); another count is one sentence."""
        value = np.asarray(value, float)
        if value.ndim and value.shape != (self.n,):
            raise ValueError(f"ThermalPlant.step: {value.size} {name} value(s) for {self.n} actuators "
                             f"({', '.join(self.names)}); give one per "
                             "actuator, in that order, or one for all")
        return np.array(np.broadcast_to(value, (self.n,)))

    def clear_faults(self) -> None:
        """Re-enable faulted actuators (as a drive's fault reset does)."""
        self.faulted[:] = False

    def _measure(self):
        net = self.layout
        readings = self.read(np.concatenate([self._x[net.sensor], self._x[net.driver[self._has_driver]]]))
        self._measured_core = readings[: self.n]
        self._measured_driver = readings[self.n :]

    def read(self, true_C: np.ndarray, noise: np.ndarray | None = None) -> np.ndarray:
        """What a thermistor on these temperatures reports (:meth:`.sensors.Thermistors.read`)."""
        return self.sensors.read(true_C, noise)

    # ---------------------------------------------------------------- blocks
    @property
    def steps_in_blocks(self) -> bool:
        """Whether :func:`~thermolimb.plant.blocks.free_block` applies: no effect makes the heat depend on the
        state or on a schedule (copper resistance, airflow, a fan, a brake, a board's load): held inputs give
        a fixed linear map."""
        return (not any(fx.state_dependent for fx in self.effects.active) and not self._schedules
                and (self.observer is None or self.observer.alpha == 0.0))

    # ---------------------------------------------------------------- outputs
    @property
    def winding_C(self) -> np.ndarray:
        """True winding temperatures (degC)."""
        return self._x[self.layout.winding].copy()

    def node_C(self, node: str) -> np.ndarray:
        """True temperature of a named network node (e.g. ``"housing"``) of every actuator."""
        out = []
        for i, spec in enumerate(self.specs):
            names = spec.network.node_names
            if node not in names:
                raise KeyError(
                    f"actuator {self.names[i]} ({spec.model}) has no node {node!r}; it has {names}"
                )
            out.append(self._x[self.layout.winding[i] + names.index(node)])
        return np.array(out)

    @property
    def measured_C(self) -> np.ndarray:
        """What the core thermistors report (lagged, noisy, quantised as switched on), degC."""
        return self._measured_core.copy()

    @property
    def driver_names(self) -> tuple[str, ...]:
        """Thermal channels of the driver boards, named ``<actuator>/driver``."""
        return tuple(f"{n}/driver" for n, has in zip(self.names, self._has_driver) if has)

    @property
    def measured_driver_C(self) -> np.ndarray:
        """What the driver-board thermistors report, for actuators that have one (degC)."""
        return self._measured_driver.copy()

    @property
    def ambient_C(self) -> float:
        return self.ambient_at(self.time_s)

    @property
    def protected_C(self) -> np.ndarray:
        """The winding temperature thermal protection acts on (degC): estimated plus its margin, or
        measured."""
        return self.protection.acted_on_C(self._measured_core, self.observer)

    def derating(self) -> np.ndarray:
        """Fraction of the commanded effort thermal protection allows each actuator now."""
        return self.protection.fraction(self.protected_C, self.winding_limits_C)

    def protection_fraction(self, effort: np.ndarray, velocity: np.ndarray | None = None,
                            dt_s: float | None = None) -> np.ndarray:
        """The share of each actuator's motor effort thermal protection allows over the next interval.

        :meth:`derating` on the temperature protection acts on; given the
        interval ``dt_s`` the efforts will be held for (and the speeds), the
        observer also caps the current so that the winding it predicts at the
        interval's end stays ``guard_K`` plus ``sigmas`` below the limit: a
        winding heats by tens of kelvin a second at peak current, faster than
        a slow control period can react to.  Field-weakening current is scaled
        by the same share.  This is the plant's one protection call: the
        robots' rigs call it every control period with that period.
        """
        effort = np.asarray(effort, dtype=float)
        cap = None
        if self.observer is not None and dt_s is not None:
            speed = np.zeros(self.n) if velocity is None else np.abs(np.asarray(velocity, float))
            current = np.sqrt(self._current_sq(effort, speed, 1.0))
            ambient = self.ambient_at(self.time_s)

            def current_cap(below):
                return self.observer.current_fraction_cap(current, below, ambient, dt_s, speed)

            cap = current_cap

        std = self.observer.winding_std_K if self.observer is not None else None
        self._applied_fraction = self.protection.share(self.protected_C, self.winding_limits_C, std, cap)
        return self._applied_fraction

    def scale_efforts(self, effort: np.ndarray, fraction: np.ndarray) -> np.ndarray:
        """Efforts whose motor share (all of it, less a series-elastic bias) is scaled by ``fraction``."""
        return scale_efforts(effort, fraction, self.effects.bias_effort)

    def derate(
        self, effort: np.ndarray, velocity: np.ndarray | None = None, dt_s: float | None = None
    ) -> np.ndarray:
        """Efforts after thermal protection (:meth:`protection_fraction` applied by :meth:`scale_efforts`)."""
        return self.scale_efforts(effort, self.protection_fraction(effort, velocity, dt_s))

    def steady_state_rise_K(self, heat_W: float, actuator: int = 0) -> float:
        """Winding rise above ambient for constant winding heat, from the network alone."""
        return heat_W * self.specs[actuator].network.total_resistance_K_per_W
