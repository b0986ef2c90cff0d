"""``thermolimb/HexapodLoadCarry-v0``: carry a payload as far as possible without overheating.

Registered by ``import hexapod_pb``.

Every decision step (1 s by default, ``decision_s``) the agent chooses how to distribute the stance
wrenches -- a blend of vertical-only, minimax and thermal-aware forces (a
convex combination of balanced distributions is balanced) -- and how fast to
walk, 0 pausing to cool.  The payload (0-5 kg), the actuators' starting
temperatures and the ambient are drawn at reset.

Action (``Box``, float32):

=====  ======================================  =====  ======
index  meaning                                 unit   range
=====  ======================================  =====  ======
0:3    weights of vertical-only, minimax,      1      [0, 1]
       thermal-aware forces (normalised)
3      walking speed, fraction of the gait's   1      [0, 1]
=====  ======================================  =====  ======

Finite actions outside ``[0, 1]`` are clipped into it (as Gymnasium's
``ClipAction`` would); a NaN or infinite action is refused.

Observation (``Box``, float32):

=======  ====  =======================================  ======
slice    size  meaning                                  unit
=======  ====  =======================================  ======
0:18     18    measured winding temperatures            degC
18:36    18    |commanded torque| / continuous torque   1
36:39    3     body velocity, body frame                m/s
39       1     payload mass                             kg
=======  ====  =======================================  ======

Reward (terms in ``info["reward_terms"]``): ``distance`` = metres made good
along x over the step; ``overheat`` = -0.05 per kelvin of the hottest
winding above 120 degC; ``fall`` = -100 once.  Terminated when an actuator
reaches its winding limit (``ActuatorSpec.winding_limit_C``, 155 degC for the
X8) or the robot falls; truncated after ``max_time_s``.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from gymnasium import spaces

from thermolimb.envs.base import RigEnv

from . import cpg
from .controller import ControllerState, ThermalContext, control_step
from .params import DAISY, FALLEN_BODY_HEIGHT_M
from .sim import HexapodSim, SimConfig
from .thermal import datasheet_bank

DECISION_S = 1.0
HOT_C = 120.0  # the overheat penalty starts here


class HexapodLoadCarryEnv(RigEnv):
    OUTCOME = "distance_m"

    def __init__(self, max_time_s: float = 60.0, decision_s: float = DECISION_S, render_mode: str | None = None):
        super().__init__(max_time_s, decision_s, render_mode)
        self.action_space = spaces.Box(0.0, 1.0, (4,), np.float32)
        low = np.r_[np.full(18, -50.0), np.zeros(18), np.full(3, -10.0), 0.0].astype(np.float32)
        high = np.r_[np.full(18, 400.0), np.full(18, 10.0), np.full(3, 10.0), 50.0].astype(np.float32)
        self.observation_space = spaces.Box(low, high, dtype=np.float32)

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed)
        rng = self.np_random
        self.payload_kg = float(rng.uniform(0.0, 5.0))
        ambient = float(rng.uniform(20.0, 35.0))
        self.sim = HexapodSim(config=SimConfig(payload_kg=self.payload_kg, ambient_C=ambient, log_capacity=self.LOG_CAPACITY),
                              seed=int(rng.integers(2**31)))
        self.sim.plant.set_temperatures(rng.uniform(40.0, 110.0, 18))
        self.gait = cpg.CPGParams()
        self.state = ControllerState(cpg.initial_state(None, self.gait))
        self.thermal = ThermalContext(datasheet_bank(ambient))
        self.reading = self.sim.read()
        self.torque = np.zeros(18)
        self.fallen = False
        return self._observation(), self._info({})

    def step(self, action):
        a = np.clip(self._begin_step(action), 0.0, 1.0)
        weights = a[:3] / a[:3].sum() if a[:3].sum() > 1e-9 else np.array([1.0, 0.0, 0.0])
        speed = float(a[3])
        gait = replace(self.gait, step_length_m=self.gait.step_length_m * speed)
        start_x = self.reading.body_position_m[0]
        blend = dict(zip(("vertical_only", "minimax", "thermal_aware"), weights))
        for _ in range(max(1, int(round(self.decision_s / self.sim.config.control_dt_s)))):
            torques, self.state, _ = control_step(self.reading, self.state, DAISY, gait, blend,
                                                  self.sim.config.control_dt_s, self.payload_kg, thermal=self.thermal,
                                                  walking=speed > 0.05)
            self.reading = self.sim.step(torques)
            self.torque = torques
            if self.reading.body_position_m[2] < FALLEN_BODY_HEIGHT_M:
                self.fallen = True
                break
        hottest = float(self.reading.temperature_C.max())
        at_limit = bool(np.any(self.reading.temperature_C >= self.sim.plant.winding_limits_C))
        terms = {"distance": float(self.reading.body_position_m[0] - start_x),
                 "overheat": -0.05 * max(0.0, hottest - HOT_C), "fall": -100.0 if self.fallen else 0.0}
        terminated = self.fallen or at_limit
        truncated = self._end_step(terminated)
        return self._observation(), float(sum(terms.values())), terminated, truncated, self._info(terms)

    def render(self):
        if self.render_mode != "rgb_array" or self.sim is None:
            return None
        return self.sim.render()

    @staticmethod
    def episode_outcome(info: dict, terminated: bool) -> dict:
        """How far the payload went, and when an actuator reached its limit (if it did)."""
        at_limit = terminated and not info["fell"]
        return {"distance_m": info["distance_m"], "time_to_limit_s": info["time_s"] if at_limit else None}

    def _observation(self) -> np.ndarray:
        r = self.reading
        norm = self.torque / DAISY.continuous_torque_per_joint_Nm
        obs = np.concatenate([r.temperature_C, np.abs(norm), r.body_velocity_m_s, [self.payload_kg]])
        return np.clip(obs, self.observation_space.low, self.observation_space.high).astype(np.float32)

    def _info(self, terms: dict) -> dict:
        return {"reward_terms": terms, "time_s": self.sim.time_s, "distance_m": float(self.reading.body_position_m[0]),
                "max_temperature_C": float(self.reading.temperature_C.max()), "fell": self.fallen,
                "payload_kg": self.payload_kg}
