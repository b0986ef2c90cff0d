"""``thermolimb/HexapodLoadCarry-v0``: carry a payload as far as possible without overheating.

Registered by ``import hexapod_pb``; spaces, units, reward and options are in
:class:`HexapodLoadCarryEnv`'s docstring (``help(env.unwrapped)``).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from gymnasium import spaces

from thermolimb.envs.base import RigEnv, checked_finite, checked_port, checked_range

from .constants import JOINTS
from .control import cpg
from .control.controller import ThermalContext
from .control.loop import ControlLoop
from .limits import LIMITS
from .params import DAISY
from .sim import HexapodSim, SimConfig
from .thermal import datasheet_bank

DECISION_S = 1.0


class HexapodLoadCarryEnv(RigEnv):
    """Carry a payload as far as possible without overheating.

    Every decision step (``decision_s``, 1 s by default) the agent chooses how
    to distribute the stance wrenches -- a blend of vertical-only, minimax and
    thermal-aware forces (a convex combination of balanced distributions is
    balanced) -- and how fast to walk, 0 pausing to cool.  The payload, the
    actuators' starting temperatures and the ambient are drawn at reset from
    the ranges given to the constructor.

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
    18:36    18    |commanded torque| / continuous effort   1
    36:39    3     body velocity, body frame                m/s
    39       1     payload mass                             kg
    =======  ====  =======================================  ======

    Reward, every term in ``info["reward_terms"]``: ``distance`` = metres made
    good along x over the step times ``distance_weight_per_m``; ``overheat`` =
    ``-overheat_weight_per_K`` per kelvin of the hottest winding reading above
    ``overheat_from_C`` (default 35 K below the winding limit, 120 degC:
    :mod:`hexapod_pb.limits`); ``fall`` = ``-fall_penalty`` once.  Terminated
    when an actuator reaches its winding limit (155 degC for the X8) or the
    robot falls; truncated after ``max_time_s``.

    Parameters
    ----------
    max_time_s, decision_s
        Episode length and decision interval (s).
    payload_range_kg, ambient_range_C, initial_temperature_range_C
        Uniform ranges the reset draws the payload (kg), the ambient (degC) and
        each actuator's starting temperature (degC) from.
    distance_weight_per_m, overheat_weight_per_K, overheat_from_C, fall_penalty
        The reward's weights (see above).
    live
        A port: stream every episode's world live to Foxglove on the monitor's channels (winding estimates,
        time to the limit, derating; :mod:`thermolimb.monitor.live`; extra 'live').  ``None``: no stream.

    ``reset(options=...)`` takes no options: the ranges are the constructor's.
    """

    OUTCOME = "distance_m"
    JOINTS = JOINTS

    def __init__(
        self,
        max_time_s: float = 60.0,
        decision_s: float = DECISION_S,
        render_mode: str | None = None,
        payload_range_kg: tuple[float, float] = (0.0, 5.0),
        ambient_range_C: tuple[float, float] = (20.0, 35.0),
        initial_temperature_range_C: tuple[float, float] = (40.0, 110.0),
        distance_weight_per_m: float = 1.0,
        overheat_weight_per_K: float = 0.05,
        overheat_from_C: float = LIMITS.warning_C,
        fall_penalty: float = 100.0,
        live: int | None = None,
    ):
        super().__init__(max_time_s, decision_s, render_mode)
        self.live = checked_port(live)
        self.payload_range_kg = checked_range("payload_range_kg", payload_range_kg, 0.0, 50.0)
        self.ambient_range_C = checked_range("ambient_range_C", ambient_range_C, -40.0, 60.0)
        self.initial_temperature_range_C = checked_range("initial_temperature_range_C",
                                                         initial_temperature_range_C, -40.0, 150.0)
        self.distance_weight_per_m = float(distance_weight_per_m)
        self.overheat_weight_per_K = float(overheat_weight_per_K)
        self.overheat_from_C = float(overheat_from_C)
        checked_finite(distance_weight_per_m=distance_weight_per_m,
                       overheat_weight_per_K=overheat_weight_per_K, overheat_from_C=overheat_from_C,
                       fall_penalty=fall_penalty)
        self.fall_penalty = float(fall_penalty)
        self.action_space = spaces.Box(0.0, 1.0, (4,), np.float32)
        low = np.r_[np.full(18, -50.0), np.zeros(18), np.full(3, -10.0), 0.0].astype(np.float32)
        high = np.r_[np.full(18, 400.0), np.full(18, 10.0), np.full(3, 10.0), 50.0].astype(np.float32)
        self.observation_space = spaces.Box(low, high, dtype=np.float32)

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed, options=options)
        rng = self.np_random
        self.payload_kg = float(rng.uniform(*self.payload_range_kg))
        ambient = float(rng.uniform(*self.ambient_range_C))
        self.sim = HexapodSim(
            config=SimConfig(payload_kg=self.payload_kg, ambient_C=ambient, log_capacity=self.LOG_CAPACITY),
            seed=int(rng.integers(2**31)),
        )
        self.sim.plant.set_temperatures(rng.uniform(*self.initial_temperature_range_C, 18))
        self.loop = ControlLoop(self.sim, DAISY, cpg.CPGParams(), self.payload_kg,
                                thermal=ThermalContext(datasheet_bank(ambient_C=ambient)))
        self.fallen = False
        return self._observation(), self._info({})

    def step(self, action):
        a = np.clip(self._begin_step(action), 0.0, 1.0)
        weights = a[:3] / a[:3].sum() if a[:3].sum() > 1e-9 else np.array([1.0, 0.0, 0.0])
        speed = float(a[3])
        loop = self.loop
        gait = replace(loop.gait, step_length_m=loop.gait.step_length_m * speed)
        start_x = loop.reading.body_position_m[0]
        blend = dict(zip(("vertical_only", "minimax", "thermal_aware"), weights))
        for _ in range(max(1, int(round(self.decision_s / self.sim.config.control_dt_s)))):
            loop.step(blend, walking=speed > 0.05, gait=gait)
            if loop.fallen:
                self.fallen = True
                break
        reading = loop.reading
        hottest = float(reading.temperature_C.max())
        at_limit = bool(np.any(reading.temperature_C >= LIMITS.winding_limits_C))
        terms = {"distance": self.distance_weight_per_m * float(reading.body_position_m[0] - start_x),
                 # 0.0 minus a penalty: no "-0.0" in info when there is none
                 "overheat": 0.0 - self.overheat_weight_per_K * max(0.0, hottest - self.overheat_from_C),
                 "fall": -self.fall_penalty if self.fallen else 0.0}
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
        r = self.loop.reading
        norm = self.loop.torques_Nm / DAISY.continuous_effort_Nm
        obs = np.concatenate([r.temperature_C, np.abs(norm), r.body_velocity_m_s, [self.payload_kg]])
        return np.clip(obs, self.observation_space.low, self.observation_space.high).astype(np.float32)

    def _info(self, terms: dict) -> dict:
        reading = self.loop.reading
        solution = self.loop.solution
        return {
            "reward_terms": terms,
            "time_s": self.sim.time_s,
            "distance_m": float(reading.body_position_m[0]),
            "max_temperature_C": float(reading.temperature_C.max()),
            "fell": self.fallen,
            "payload_kg": self.payload_kg,
            "stance_solver": None if solution is None else solution.label,
            "stance_fallbacks": self.loop.fallbacks,
            **self.sim.plant_faults(),
        }
