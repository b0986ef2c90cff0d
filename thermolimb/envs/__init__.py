"""Gymnasium environments of the suite, registered when ``thermolimb`` is imported.

``gymnasium.make("thermolimb/HumanoidThermalRecovery-v0")`` and
``gymnasium.make("thermolimb/HexapodLoadCarry-v0")``; the robots load only when
an environment is made.
"""

from __future__ import annotations

import gymnasium as gym

HUMANOID_ID = "thermolimb/HumanoidThermalRecovery-v0"
HEXAPOD_ID = "thermolimb/HexapodLoadCarry-v0"


def register_envs() -> None:
    if HUMANOID_ID not in gym.registry:
        gym.register(HUMANOID_ID, entry_point="thermolimb.envs.humanoid_recovery:HumanoidThermalRecoveryEnv")
    if HEXAPOD_ID not in gym.registry:
        gym.register(HEXAPOD_ID, entry_point="thermolimb.envs.hexapod_load_carry:HexapodLoadCarryEnv")
