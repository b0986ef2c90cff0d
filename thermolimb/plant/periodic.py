"""Hours of a periodic duty in milliseconds: the plant's network propagated cycle by cycle.

Once a gait is periodic, every control interval of a cycle maps the plant's
state affinely, ``x+ = M_k x + c_k`` (the exact zero-order-hold step of
:class:`~thermolimb.plant.ThermalPlant`, with the state-dependent heat --
copper resistance, motion cooling -- linear in the state).  Composing the
intervals of one cycle gives the cycle map ``x(T) = M x(0) + c``; iterating it
propagates the network over hours for the cost of one matrix-vector product
per cycle, and the temperatures inside a cycle follow from its start state
through the stacked interval maps.  Nothing is approximated: for the same
efforts, velocities and ambient it is the plant stepped one interval at a
time (``tests/test_periodic.py`` checks that to rounding).

What it leaves out is what makes the duty non-periodic: thermal protection
(the propagation answers *when* it would start), a drifting ambient, and a
controller that changes the duty as the robot heats (propagate in windows,
re-measuring the cycle each window, as :mod:`hexapod_pb.endurance` does).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .plant import ThermalPlant


@dataclass(frozen=True)
class Crossing:
    """The first control interval whose end state has a winding at or above the threshold."""

    time_s: float  # from the start of the propagation
    actuator: int


@dataclass(frozen=True)
class Propagation:
    """Winding temperatures at every cycle start, and the first crossing of the threshold (if any)."""

    cycle_start_s: np.ndarray  # (k,)
    winding_C: np.ndarray  # (k, n) at each cycle start
    peak_winding_C: np.ndarray  # (k, n) hottest within each cycle (interval ends)
    mean_winding_C: np.ndarray  # (k, n) mean over each cycle's interval ends
    final_state: np.ndarray  # the plant's state vector at the end
    crossing: Crossing | None


class CycleMap:
    """The affine maps of one cycle of held efforts and velocities on a plant's network.

    Parameters
    ----------
    plant
        Gives the network, the effects and the ambient (held at its value at
        the plant's current time).  Its state is not changed.
    efforts, velocities
        ``(steps, n)`` arrays, one row per control interval of the cycle.
    dt_s
        The control interval (s).
    """

    def __init__(self, plant: ThermalPlant, efforts: np.ndarray, velocities: np.ndarray, dt_s: float):
        efforts = np.asarray(efforts, float)
        velocities = np.asarray(velocities, float)
        if (
            efforts.ndim != 2
            or efforts.shape[1] != plant.n
            or velocities.shape != efforts.shape
            or len(efforts) == 0
        ):
            raise ValueError(f"a cycle needs efforts and velocities of shape (steps, {plant.n}), got "
                             f"{efforts.shape} and {velocities.shape}")
        if not (np.all(np.isfinite(efforts)) and np.all(np.isfinite(velocities))):
            raise ValueError("a cycle's efforts and velocities must be finite")
        # the drives hold an effort at the peak
        efforts = np.clip(efforts, -plant.peak_effort, plant.peak_effort)
        if plant.effects.ambient_variation is not None:
            raise ValueError("the ambient drifts: the duty is not periodic, step the plant instead")
        self.dt_s = float(dt_s)
        self.steps = len(efforts)
        self.period_s = self.steps * self.dt_s
        self.ambient_C = plant.ambient_C
        Phi, Gamma = plant._discretisation(self.dt_s)
        n_states = Phi.shape[0]
        self.winding_index = plant.layout.winding.copy()
        step_M, step_c = np.empty((self.steps, n_states, n_states)), np.empty((self.steps, n_states))
        for k in range(self.steps):
            constant, per_kelvin = plant.heat_affine(efforts[k], velocities[k])
            step_M[k] = Phi + Gamma[:, :n_states] * per_kelvin[None, :]
            step_c[k] = Gamma[:, :n_states] @ constant + Gamma[:, n_states] * self.ambient_C
        # within the cycle: x_k = P_k x_0 + d_k after k + 1 intervals
        P, d = np.eye(n_states), np.zeros(n_states)
        self._within_P = np.empty((self.steps, len(self.winding_index), n_states))
        self._within_d = np.empty((self.steps, len(self.winding_index)))
        for k in range(self.steps):
            P, d = step_M[k] @ P, step_M[k] @ d + step_c[k]
            self._within_P[k] = P[self.winding_index]
            self._within_d[k] = d[self.winding_index]
        self.M, self.c = P, d

    def followed_by(self, other: CycleMap) -> CycleMap:
        """This cycle then ``other`` (same network, ambient and interval) as one cycle: walking, then a
        pause."""
        if (other.dt_s != self.dt_s or other.M.shape != self.M.shape or other.ambient_C != self.ambient_C
                or not np.array_equal(other.winding_index, self.winding_index)):
            raise ValueError("cycles join only on the same network, ambient and control interval")
        joined = object.__new__(CycleMap)
        joined.dt_s, joined.ambient_C, joined.winding_index = self.dt_s, self.ambient_C, self.winding_index
        joined.steps = self.steps + other.steps
        joined.period_s = joined.steps * joined.dt_s
        joined._within_P = np.concatenate([self._within_P, other._within_P @ self.M])
        joined._within_d = np.concatenate([self._within_d, other._within_P @ self.c + other._within_d])
        joined.M, joined.c = other.M @ self.M, other.M @ self.c + other.c
        return joined

    def within(self, x0: np.ndarray) -> np.ndarray:
        """Winding temperatures (steps, n) at the end of every interval of a cycle started at state ``x0``."""
        return self._within_P @ x0 + self._within_d

    def steady_state(self) -> np.ndarray:
        """The state the cycle repeats once the transient has died out (every network here leaks to
        ambient)."""
        return np.linalg.solve(np.eye(len(self.c)) - self.M, self.c)

    def steady_peak_C(self) -> np.ndarray:
        """Hottest winding (degC) of each actuator within the periodic steady cycle: if below the threshold,
        it never gets there."""
        return self.within(self.steady_state()).max(axis=0)

    def propagate(
        self, x0: np.ndarray, duration_s: float, threshold_C: float | np.ndarray = np.inf
    ) -> Propagation:
        """Whole cycles from state ``x0`` for ``duration_s`` (rounded up to whole cycles), stopping at the end
        of the cycle in which a winding first reaches ``threshold_C`` (per actuator or one for all)."""
        if not (np.isfinite(duration_s) and duration_s > 0):
            raise ValueError(f"duration_s must be positive and finite, got {duration_s}")
        cycles = int(np.ceil(duration_s / self.period_s - 1e-9))
        threshold = np.broadcast_to(np.asarray(threshold_C, float), (len(self.winding_index),))
        x = np.asarray(x0, float).copy()
        starts, peaks, means = [], [], []
        crossing = None
        for i in range(cycles):
            inside = self.within(x)
            starts.append(x[self.winding_index])
            peaks.append(inside.max(axis=0))
            means.append(inside.mean(axis=0))
            above = inside >= threshold
            if above.any():
                k, j = np.argwhere(above)[0]
                crossing = Crossing(time_s=i * self.period_s + (k + 1) * self.dt_s, actuator=int(j))
                x = self.M @ x + self.c
                break
            x = self.M @ x + self.c
        return Propagation(np.arange(len(starts)) * self.period_s, np.array(starts), np.array(peaks),
                           np.array(means), x, crossing)
