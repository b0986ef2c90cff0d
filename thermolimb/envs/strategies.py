"""Strategies as policies: ``policy(env, observation) -> action`` for any instance of the environments.

Humanoid: ``thermal_aware`` (the seed's Eq. 33: the contact mode whose
thermally best configuration has the lowest potential, planned with the
actuators' first-order models), ``minimum_effort`` (the mode of least
normalised effort), ``always_double_support`` and ``random``.
Hexapod: ``vertical_only``, ``minimax``, ``thermal_aware`` (full weight on
that distribution, walking at full speed) and ``random``.

A policy that plans reads the robot's state from ``env.unwrapped`` (what the
controller on the rig would know: configuration and measured temperatures).
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from ..errors import UsageError
from . import HEXAPOD_ID, HUMANOID_ID

Policy = Callable[[object, np.ndarray], object]


class RandomPolicy:
    """Uniform actions from the action space, with its own seeded generator."""

    def __init__(self, seed: int = 0):
        self.seed = seed

    def __call__(self, env, observation):
        space = env.action_space
        if not hasattr(self, "_seeded"):
            space.seed(self.seed)
            self._seeded = True
        return space.sample()


class HumanoidModePolicy:
    """Eq. 33 over the three contact modes with an objective: thermal potential or minimum effort."""

    def __init__(self, objective: str, replan_s: float = 6.0):
        if objective not in ("thermal", "effort"):
            raise ValueError(f"objective must be 'thermal' or 'effort', got {objective!r}")
        self.objective = objective
        self.replan_s = replan_s
        self._solver = None
        self._last = (None, -np.inf)

    def __call__(self, env, observation):
        from humanoid_pb.actuators import VALKYRIE_NETWORK, actuator_specs
        from humanoid_pb.constants import SIDES
        from humanoid_pb.fast_ik import FastThermalIK
        from humanoid_pb.poses import single_support
        from humanoid_pb.potential import MinimumEffort, ThermalPotential
        from thermolimb.model import FirstOrderBank

        from .humanoid_recovery import MODES

        e = env.unwrapped
        mode, when = self._last
        if mode is not None and e.sim.time_s - when < self.replan_s:
            return MODES.index(mode)
        body = e.sim.body
        if self._solver is None or self._solver.body is not body:
            self._solver = FastThermalIK(body)
        specs = actuator_specs(body.params)
        if self.objective == "thermal":
            beta = np.array([s.winding_resistance_ohm * VALKYRIE_NETWORK.resistance_K_per_W[0] / s.effort_per_amp**2
                             for s in specs])
            rc = VALKYRIE_NETWORK.capacity_J_per_K[0] * VALKYRIE_NETWORK.resistance_K_per_W[0]
            n = len(specs)
            bank = FirstOrderBank(np.full(n, rc), beta, np.zeros(n), np.full(n, e.sim.plant.ambient_C))
            objective = ThermalPotential.from_measurement(bank, e.reading.temperature_C)
        else:
            objective = MinimumEffort(np.array([s.effort_limit for s in specs]))
        q0 = e.executor.q_nominal
        starts = {"double": q0, **{s: single_support(body, q0, s) for s in SIDES}}
        results = {m: self._solver.solve(starts[m], m, objective, max_iter=10) for m in starts}
        mode = min(results, key=lambda m: results[m].potential)
        self._last = (mode, e.sim.time_s)
        return MODES.index(mode)


def make_policy(env_id: str, name: str, seed: int = 0) -> Policy:
    """A fresh policy by name for an environment id."""
    if name == "random":
        return RandomPolicy(seed)
    if env_id == HUMANOID_ID:
        if name == "thermal_aware":
            return HumanoidModePolicy("thermal")
        if name == "minimum_effort":
            return HumanoidModePolicy("effort")
        if name == "always_double_support":
            return lambda env, obs: 0
    elif env_id == HEXAPOD_ID:
        fixed = {"vertical_only": [1, 0, 0, 1], "minimax": [0, 1, 0, 1], "thermal_aware": [0, 0, 1, 1]}
        if name in fixed:
            action = np.array(fixed[name], dtype=np.float32)
            return lambda env, obs: action
    raise UsageError(f"no strategy {name!r} for {env_id}; available: {', '.join(STRATEGIES[env_id])}")


STRATEGIES = {
    HUMANOID_ID: ("thermal_aware", "minimum_effort", "always_double_support", "random"),
    HEXAPOD_ID: ("vertical_only", "minimax", "thermal_aware", "random"),
}
