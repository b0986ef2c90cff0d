"""Thermal networks and actuator electrical data for the plant.

Numbers are from ``shared/reference/facts.md`` (HEBI X-series vendor model);
where a number is chosen here rather than read, its line says so.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..util.errors import check_range


@dataclass(frozen=True)
class ThermalNetwork:
    """A chain of thermal masses: node 0 is the winding, the last node loses heat to ambient.

    ``resistance_K_per_W[i]`` joins node ``i`` to node ``i + 1``; the last one
    joins the last node to ambient.
    """

    node_names: tuple[str, ...]
    capacity_J_per_K: tuple[float, ...]
    resistance_K_per_W: tuple[float, ...]

    def __post_init__(self):
        n = len(self.node_names)
        if n == 0 or len(self.capacity_J_per_K) != n or len(self.resistance_K_per_W) != n:
            raise ValueError(
                f"ThermalNetwork needs one capacity and one resistance per node; got {n} names, "
                f"{len(self.capacity_J_per_K)} capacities, {len(self.resistance_K_per_W)} resistances"
            )
        bad = [
            v for v in (*self.capacity_J_per_K, *self.resistance_K_per_W) if not (np.isfinite(v) and v > 0)
        ]
        if bad:
            raise ValueError(f"thermal capacities and resistances must be positive and finite, got {bad}")

    @property
    def n_nodes(self) -> int:
        return len(self.node_names)

    @property
    def total_resistance_K_per_W(self) -> float:
        """Winding to ambient: the steady-state rise per watt of winding heat."""
        return float(sum(self.resistance_K_per_W))

    def system_matrix(self) -> np.ndarray:
        """``A`` of ``C dT/dt = A_G T + ...`` divided by C, for the chain alone (1/s)."""
        n = self.n_nodes
        G = 1.0 / np.asarray(self.resistance_K_per_W)
        C = np.asarray(self.capacity_J_per_K)
        A = np.zeros((n, n))
        for i in range(n):
            A[i, i] -= G[i]
            if i + 1 < n:
                A[i, i + 1] += G[i]
                A[i + 1, i] += G[i]
                A[i + 1, i + 1] -= G[i]
        return A / C[:, None]

    @property
    def time_constants_s(self) -> np.ndarray:
        """Time constants of the chain, fastest first."""
        return np.sort(-1.0 / np.linalg.eigvals(self.system_matrix()).real)


# HEBI X8 vendor model: winding -> housing -> body -> environment.
X8_NETWORK = ThermalNetwork(("winding", "housing", "body"), (0.638, 24.1, 2500.0), (2.256, 1.0, 4.0))
X5_NETWORK = ThermalNetwork(("winding", "housing", "body"), (0.367, 16.6, 1250.0), (4.626, 1.0, 8.0))
# Chosen here: the X8 winding and housing merged into one mass that loses heat
# through the housing-to-body path to a body held at ambient (tau = 24.7 * 3.256 = 80 s).
FIRST_ORDER_NETWORK = ThermalNetwork(("winding",), (0.638 + 24.1,), (2.256 + 1.0,))
# Chosen here: the same merged winding on a small, slower frame mass (tau about 35 s and 1200 s).
SECOND_ORDER_NETWORK = ThermalNetwork(("winding", "frame"), (24.7, 300.0), (1.3, 4.0))

NETWORKS = {"x8": X8_NETWORK, "x5": X5_NETWORK, "first_order": FIRST_ORDER_NETWORK,
            "second_order": SECOND_ORDER_NETWORK}


@dataclass
class Layout:
    """Where each actuator's nodes sit in the plant's state, and the network effects wire into (``A`` changes
    in place while effects wire it): node indices per actuator (``driver`` is -1 without a board), the system
    matrix, each node's inverse capacity (0 for a massless sensor node), the ambient's input and each outer
    node's conductance to ambient."""

    winding: np.ndarray
    housing: np.ndarray
    outer: np.ndarray
    sensor: np.ndarray
    driver: np.ndarray
    A: np.ndarray
    inv_capacity: np.ndarray
    b_amb: np.ndarray
    outer_conductance: np.ndarray

    @property
    def n_states(self) -> int:
        return self.A.shape[0]

    @classmethod
    def build(cls, specs, effects) -> "Layout":
        """The network of ``specs`` side by side, each chain's winding first, then a node per lagging
        thermistor (when an effect asks for one) and per driver board; then every effect that is on wires its
        part."""
        idx = 0
        winding, housing, outer, sensor, driver = [], [], [], [], []
        blocks = []
        for spec in specs:
            net = spec.network
            winding.append(idx)
            housing.append(idx + 1 if net.n_nodes > 1 else idx)
            outer.append(idx + net.n_nodes - 1)
            blocks.append((idx, spec))
            idx += net.n_nodes
        lagging = any(fx.sensor_node for fx in effects.active)  # each thermistor is a node of its own
        for i in range(len(specs)):
            sensor.append(idx if lagging else winding[i])
            idx += int(lagging)
        for spec in specs:
            driver.append(idx if spec.driver is not None else -1)
            idx += int(spec.driver is not None)
        A = np.zeros((idx, idx))
        inv_capacity = np.zeros(idx)  # heat input (W) -> dT/dt; zero for massless sensor nodes
        b_amb = np.zeros(idx)
        outer_conductance = np.zeros(len(specs))
        for i, (start, spec) in enumerate(blocks):
            net = spec.network
            m = net.n_nodes
            A[start : start + m, start : start + m] = net.system_matrix()
            C = np.asarray(net.capacity_J_per_K)
            inv_capacity[start : start + m] = 1.0 / C
            outer_conductance[i] = 1.0 / net.resistance_K_per_W[-1]
            b_amb[outer[i]] += outer_conductance[i] / C[-1]
            if spec.driver is not None:
                d = driver[i]
                g = 1.0 / spec.driver.resistance_K_per_W
                A[d, d] = -g / spec.driver.capacity_J_per_K
                b_amb[d] = g / spec.driver.capacity_J_per_K
                inv_capacity[d] = 1.0 / spec.driver.capacity_J_per_K
        net = cls(np.array(winding), np.array(housing), np.array(outer), np.array(sensor), np.array(driver),
                  A, inv_capacity, b_amb, outer_conductance)
        for fx in effects.active:
            fx.wire(net)
        return net


@dataclass(frozen=True)
class DriverSpec:
    """The motor driver (H-bridge) board: the same current heats it (seed Fig. 2).

    The values are chosen here (the vendor model has no driver node): a bridge
    with 1 ohm effective loss resistance on a 20 J/K board, 4 K/W to ambient (tau = 80 s).
    """

    loss_resistance_ohm: float = 1.0
    capacity_J_per_K: float = 20.0
    resistance_K_per_W: float = 4.0


@dataclass(frozen=True)
class ActuatorSpec:
    """Electrical and thermal data of one actuator model."""

    model: str
    effort_per_amp: float  # N m/A at the output (torque constant x gear ratio), or N/A for linear
    winding_resistance_ohm: float  # terminal resistance at 25 degC
    effort_limit: float  # N m or N
    continuous_effort: float  # N m or N, what the actuator can hold indefinitely
    velocity_limit: float  # rad/s or m/s
    network: ThermalNetwork = X8_NETWORK
    winding_limit_C: float = 155.0
    driver: DriverSpec | None = DriverSpec()

    def __post_init__(self):
        for name in (
            "effort_per_amp",
            "winding_resistance_ohm",
            "effort_limit",
            "continuous_effort",
            "velocity_limit",
        ):
            value = getattr(self, name)
            if not (np.isfinite(value) and value > 0):
                raise ValueError(
                    f"ActuatorSpec({self.model}).{name} must be positive and finite, got {value}"
                )
        check_range(f"ActuatorSpec({self.model})", "winding_limit_C", self.winding_limit_C, 20.0, 400.0,
                    "degC")
        if self.continuous_effort > self.effort_limit:
            raise ValueError(f"ActuatorSpec({self.model}): continuous_effort "
                             f"= {self.continuous_effort:g} is above "
                             f"effort_limit = {self.effort_limit:g}; an actuator holds at most its peak")

    def first_order(self, lumped_nodes: int = 1) -> tuple[float, float]:
        """Jorgensen et al.'s Eq. 5 parameters ``(RC_s, betaR_K_per_effort2)`` from this datasheet (their Eqs.
        2-5).

        The first ``lumped_nodes`` nodes of the network (from the winding
        out) are lumped into one mass and the rest taken as the slow
        "ambient": ``RC = (C_1 + ... + C_n)(R_1 + ... + R_n)`` and
        ``betaR = R_e (R_1 + ... + R_n) / k^2`` with ``k`` the effort per amp.
        This is the one conversion from a datasheet to Jorgensen et al.'s model.
        """
        net = self.network
        if not 1 <= lumped_nodes <= net.n_nodes:
            raise ValueError(f"ActuatorSpec({self.model}).first_order lumps "
                             f"1 to {net.n_nodes} nodes, got {lumped_nodes}")
        resistance = float(np.sum(net.resistance_K_per_W[:lumped_nodes]))
        capacity = float(np.sum(net.capacity_J_per_K[:lumped_nodes]))
        return resistance * capacity, self.winding_resistance_ohm * resistance / self.effort_per_amp**2


_X8_TORQUE_CONSTANT_NM_PER_A = 9.32e-3
X8_9 = ActuatorSpec("X8-9", _X8_TORQUE_CONSTANT_NM_PER_A * 762.22, 3.19, 20.0, 8.0, 3.14)
X8_16 = ActuatorSpec("X8-16", _X8_TORQUE_CONSTANT_NM_PER_A * 1462.22, 3.19, 38.0, 16.0, 1.57)
ACTUATOR_SPECS = {"X8-9": X8_9, "X8-16": X8_16}
