"""The humanoid's strategies as policies of ``thermolimb/HumanoidThermalRecovery-v0``.

``thermal_aware`` (Jorgensen et al.'s Eq. 33 over the modes the environment's actions
hold: the contact mode whose nominal posture, held with Eq. 23's torques, has
the lowest potential, planned with models identified from a calibration run
of the robot itself -- never its plant's parameters or the true ambient),
``minimum_effort`` (the mode of least normalised effort, likewise) and
``always_double_support`` (``random`` comes from the core).
"""

from __future__ import annotations

import numpy as np

from thermolimb.envs.policies import constant_policy

from .constants import CONTACT_MODES
from .control.planner import ContactModePlanner

CALIBRATION_S = 90.0  # double support, then each foot in turn (humanoid_pb.calibration.calibrate)
_BANKS = {}


def _identified(env, specs, duration_s: float, seed: int):
    key = (specs, duration_s, seed)
    if key not in _BANKS:
        _BANKS[key] = env.calibration_run(duration_s, seed).bank
    return _BANKS[key]


class HumanoidModePolicy:
    """Re-plans the contact mode every ``replan_s`` of simulated time with a :class:`ContactModePlanner`."""

    def __init__(
        self, objective: str, replan_s: float = 6.0, calibration_s: float = CALIBRATION_S, seed: int = 0
    ):
        self.objective = objective
        self.replan_s = replan_s
        self.calibration_s = calibration_s
        self.seed = seed
        self._planner = None
        self._last = (None, -np.inf)

    def models(self, env):
        """The bank identified from this robot's calibration run (run once per robot and process)."""
        return _identified(env, (env.actuator_specs, env.scenario.name), self.calibration_s, self.seed)

    def __call__(self, env, observation):
        e = env.unwrapped
        mode, when = self._last
        if mode is not None and e.sim.time_s - when < self.replan_s:
            return CONTACT_MODES.index(mode)
        body = e.sim.body
        if self._planner is None or self._planner.body is not body:
            self._planner = ContactModePlanner(body, self.objective, max_iter=10)
        bank = self.models(e) if self.objective == "thermal" else None
        mode = self._planner.plan_nominal(e.executor.q_nominal, bank, e.reading.temperature_C)
        self._last = (mode, e.sim.time_s)
        return CONTACT_MODES.index(mode)


POLICIES = {
    "thermal_aware": lambda seed=0: HumanoidModePolicy("thermal", seed=seed),
    "minimum_effort": lambda seed=0: HumanoidModePolicy("effort"),
    "always_double_support": constant_policy(CONTACT_MODES.index("double")),
}
