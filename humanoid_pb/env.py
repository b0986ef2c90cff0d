"""``thermolimb/HumanoidThermalRecovery-v0``: recover a humanoid's hot actuators without falling.

Registered by ``import humanoid_pb``; spaces, units, reward and options are in
:class:`HumanoidThermalRecoveryEnv`'s docstring (``help(env.unwrapped)``).
"""

from __future__ import annotations

from typing import Sequence

import numpy as np
from gymnasium import spaces

from thermolimb.envs.base import RigEnv, checked_finite, checked_port, checked_range
from thermolimb.plant import ActuatorSpec
from thermolimb.rig import RigConfig

from .calibration import calibrate
from .constants import ACTUATORS, CONTACT_MODES, JOINTS, SIDES, leg_actuators, leg_joint
from .control.executor import Executor
from .limits import LIMITS
from .model.actuation import effort_limits
from .params import FALLEN_PELVIS_HEIGHT_M, VALKYRIE
from .readings import roll_pitch_rad
from .scenarios import DEFAULT
from .scenarios import scenario as get_scenario
from .sim import HumanoidSim

ACTION_SCALE = np.array([0.15, 0.08, 0.15, 0.1])
DECISION_S = 1.5
# windings heated by a minute or two of balancing sit on housings that have barely warmed (2000 s time
# constant)
HOUSING_WARMING_K = 5.0


class HumanoidThermalRecoveryEnv(RigEnv):
    """Recover a humanoid's hot actuators without falling.

    The humanoid starts standing in double support with one leg's actuators
    hot (which leg, how hot and the ambient are drawn at reset from the
    constructor's ranges, around Jorgensen et al.'s experiment: the windings hot,
    their housings within ``housing_warming_K`` of ambient, as after a minute
    or two of balancing on one leg).  Every decision step (1.5 s) the agent
    picks a contact mode -- or, with ``action_type="configuration"``, a
    posture offset -- and the environment runs the balance controller and the
    thermal plant in between.  Mode changes go through the nominal crouch, as
    in Jorgensen et al.

    Action (``action_type="mode"``): ``Discrete(3)``: 0 double support, 1 left
    single support, 2 right single support.

    Action (``action_type="configuration"``): ``Box(-1, 1, (4,))`` scaled to
    offsets of the double-support crouch:

    =====  ==============================  =========  =====
    index  meaning                         unit       range
    =====  ==============================  =========  =====
    0      crouch depth (hip/knee)         rad        +-0.15
    1      lateral lean (hip/ankle roll)   rad        +-0.08
    2      torso pitch                     rad        +-0.15
    3      torso roll                      rad        +-0.1
    =====  ==============================  =========  =====

    Observation (``Box``, float32):

    =============  ====  ============================================  ======
    slice          size  meaning                                       unit
    =============  ====  ============================================  ======
    0:23           23    measured actuator temperatures                degC
    23:46          23    actuator efforts / effort limits              1
    46:49          3     contact mode, one-hot (double, left, right)   1
    49:52          3     pelvis height, roll, pitch                    m, rad
    52:58          6     pelvis linear and angular velocity            m/s, rad/s
    58:60          2     centre of mass minus the feet's midpoint, xy  m
    =============  ====  ============================================  ======

    Reward (each term in ``info["reward_terms"]``, the reward is their sum):
    ``cooling`` = ``cooling_weight_per_K`` x the fall of the hottest
    actuator's temperature over the step (K); ``warning`` =
    ``-warning_weight`` per actuator above the warning level (``LIMITS.warning_C``, 75 degC), averaged
    over the step; ``fall`` = ``-fall_penalty`` once; ``effort`` =
    ``-effort_weight`` x the mean squared normalised effort.  Terminated when
    every actuator is below the recovered level (``LIMITS.recovered_C``, 70 degC) or the robot falls;
    truncated after ``max_time_s``.  ``reset(seed=...)`` rebuilds the world,
    so the same seed and actions give the same trajectory; ``reset`` takes no
    options (the ranges are the constructor's).

    Parameters
    ----------
    action_type
        ``"mode"`` or ``"configuration"`` (above).
    max_time_s
        Episode length (s).
    actuator_specs
        The robot's actuators if not the datasheet's (a worn or different
        robot); :meth:`calibration_run` identifies models on it.
    scenario
        ``"ankle"`` (default) or ``"walking"`` (:mod:`humanoid_pb.scenarios`): the stance the robot holds
        (the crouch, or bent knees near walking height) and, without ``actuator_specs``, how its actuators are
        sized.  ``info["hot_recovery_s"]`` is when the hot leg's actuators were all below 70 degC.
    ambient_range_C, hot_range_C, cool_range_C
        Uniform ranges of the ambient, the hot leg's windings and every other
        winding at reset (degC).
    housing_warming_K
        Housings start up to this much above ambient (K).
    cooling_weight_per_K, warning_weight, fall_penalty, effort_weight
        The reward's weights (above).
    live
        A port: stream every episode's world live to Foxglove on the monitor's channels (winding estimates,
        time to the limit, derating; :mod:`thermolimb.monitor.live`; extra 'live').  ``None``: no stream.
    """

    OUTCOME = "recovery_s"
    JOINTS = JOINTS

    def __init__(
        self,
        action_type: str = "mode",
        max_time_s: float = 90.0,
        render_mode: str | None = None,
        actuator_specs: Sequence[ActuatorSpec] | None = None,
        ambient_range_C: tuple[float, float] = (20.0, 30.0),
        hot_range_C: tuple[float, float] = (72.0, 80.0),
        cool_range_C: tuple[float, float] = (35.0, 50.0),
        housing_warming_K: float = HOUSING_WARMING_K,
        cooling_weight_per_K: float = 1.0,
        warning_weight: float = 0.5,
        fall_penalty: float = 100.0,
        effort_weight: float = 0.01,
        scenario: str = DEFAULT,
        live: int | None = None,
    ):
        super().__init__(max_time_s, DECISION_S, render_mode)
        self.live = checked_port(live)
        self.scenario = get_scenario(scenario)
        self.ambient_range_C = checked_range("ambient_range_C", ambient_range_C, -40.0, 60.0)
        self.hot_range_C = checked_range("hot_range_C", hot_range_C, -40.0, 150.0)
        self.cool_range_C = checked_range("cool_range_C", cool_range_C, -40.0, 150.0)
        if not 0.0 <= housing_warming_K <= 100.0:
            raise ValueError(f"housing_warming_K must be within 0..100 K, got {housing_warming_K!r}")
        self.housing_warming_K = float(housing_warming_K)
        checked_finite(cooling_weight_per_K=cooling_weight_per_K, warning_weight=warning_weight,
                       fall_penalty=fall_penalty, effort_weight=effort_weight)
        self.cooling_weight_per_K = float(cooling_weight_per_K)
        self.warning_weight = float(warning_weight)
        self.fall_penalty = float(fall_penalty)
        self.effort_weight = float(effort_weight)
        self.actuator_specs = None if actuator_specs is None else tuple(actuator_specs)
        if action_type not in ("mode", "configuration"):
            raise ValueError(f"action_type must be 'mode' or 'configuration', got {action_type!r}")
        self.action_type = action_type
        self.limits = effort_limits(VALKYRIE)
        self.n_act = len(ACTUATORS)
        self.action_space = (
            spaces.Discrete(3) if action_type == "mode" else spaces.Box(-1.0, 1.0, (4,), np.float32)
        )
        low = np.r_[
            np.full(23, -50.0),
            np.full(23, -10.0),
            np.zeros(3),
            0.0,
            -np.pi,
            -np.pi,
            np.full(6, -50.0),
            np.full(2, -2.0),
        ].astype(np.float32)
        high = np.r_[np.full(23, 400.0), np.full(23, 10.0), np.ones(3), 3.0, np.pi, np.pi, np.full(6, 50.0),
                     np.full(2, 2.0)].astype(np.float32)
        self.observation_space = spaces.Box(low, high, dtype=np.float32)

    def calibration_run(self, duration_s: float, seed: int = 0):
        """Models identified from a calibration run of this robot (its own actuators, whatever its datasheet
        says): what a thermal-aware policy plans with (a
        :class:`~thermolimb.identification.calibration.Calibration`)."""
        return calibrate(duration_s, seed, specs=self.actuator_specs, scenario=self.scenario)

    # ------------------------------------------------------------------ gym API
    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed, options=options)
        rng = self.np_random
        ambient = float(rng.uniform(*self.ambient_range_C))
        self.hot_side = SIDES[int(rng.integers(len(SIDES)))]
        temperatures = rng.uniform(*self.cool_range_C, self.n_act)
        for a in leg_actuators(self.hot_side):
            temperatures[ACTUATORS.index(a)] = rng.uniform(*self.hot_range_C)
        housings = ambient + rng.uniform(0.0, self.housing_warming_K, self.n_act)
        config = RigConfig(physics_hz=1000.0, control_hz=50.0, ambient_C=ambient,
                           log_capacity=self.LOG_CAPACITY)
        self.sim = HumanoidSim(config=config, seed=int(rng.integers(2**31)), specs=self.actuator_specs,
                               scenario=self.scenario)
        self.sim.plant.set_temperatures(temperatures, rest_C=housings)
        self.executor = Executor(self.sim)
        self.reading = self.sim.read()
        self.fallen = False
        self.hot_leg = [ACTUATORS.index(a) for a in leg_actuators(self.hot_side)]
        self.hot_recovery_s = None
        return self._observation(), self._info({})

    def step(self, action):
        action = self._begin_step(action)
        before = self.reading.temperature_C.max()
        self._apply(action)
        steps = int(round(self.decision_s / self.sim.config.control_dt_s))
        warning = 0.0
        for _ in range(steps):
            self.reading = self.executor.tick(self.reading)
            warning += np.sum(self.reading.temperature_C > LIMITS.warning_C) / steps
            if (
                self.hot_recovery_s is None
                and self.reading.temperature_C[self.hot_leg].max() < LIMITS.recovered_C
            ):
                self.hot_recovery_s = self.sim.time_s
            if self.reading.base_position_m[2] < FALLEN_PELVIS_HEIGHT_M:
                self.fallen = True
                break
        efforts = self.sim.last_efforts / self.limits
        terms = {
            "cooling": self.cooling_weight_per_K * float(before - self.reading.temperature_C.max()),
            "warning": 0.0 - self.warning_weight * float(warning),  # no "-0.0" in info when there is none
            "fall": -self.fall_penalty if self.fallen else 0.0,
            "effort": -self.effort_weight * float(np.mean(efforts**2)),
        }
        recovered = bool(self.reading.temperature_C.max() < LIMITS.recovered_C)
        terminated = recovered or self.fallen
        truncated = self._end_step(terminated)
        return (
            self._observation(),
            float(sum(terms.values())),
            terminated,
            truncated,
            self._info(terms, recovered),
        )

    def render(self):
        if self.render_mode == "rgb_array" and self.sim is not None:
            return self.sim.render(240, 240)
        return None

    @staticmethod
    def episode_outcome(info: dict, terminated: bool) -> dict:
        """Whether the hot actuators recovered, and how long it took."""
        return {"recovered": info["recovered"], "recovery_s": info["time_s"] if info["recovered"] else None,
                "hot_recovery_s": info["hot_recovery_s"]}

    # ------------------------------------------------------------------ helpers
    def _apply(self, action):
        ex = self.executor
        if self.action_type == "mode":
            mode = CONTACT_MODES[int(action)]
            if mode != ex.mode and not ex.moving:
                ex.go(mode)
            return
        if ex.mode != "double" and not ex.moving:
            ex.go("double")
        if ex.moving:
            return
        a = np.clip(np.asarray(action, float), -1.0, 1.0) * ACTION_SCALE
        angles = ex.nominal_angles.copy()
        for side in SIDES:
            for joint, gain in (("hip_pitch", -a[0]), ("knee", 2 * a[0]), ("ankle_pitch", -a[0]),
                                ("hip_roll", a[1]), ("ankle_roll", -a[1])):
                angles[JOINTS.index(leg_joint(side, joint))] += gain
        angles[JOINTS.index("torso_pitch")] += a[2]
        angles[JOINTS.index("torso_roll")] += a[3]
        ex.go("double", angles)  # a smooth move to the new posture

    def _observation(self) -> np.ndarray:
        r = self.reading
        sim = self.sim
        efforts = sim.last_efforts / self.limits
        mode = np.zeros(3)
        mode[CONTACT_MODES.index(self.executor.mode)] = 1.0
        roll, pitch = roll_pitch_rad(r.base_quaternion_xyzw)
        q = sim.pinocchio_q(r)
        feet = sim.body.sole_poses(q)
        mid = 0.5 * (feet["left"].translation + feet["right"].translation)
        com = sim.body.com(q)
        obs = np.concatenate([r.temperature_C, efforts, mode, [r.base_position_m[2], roll, pitch],
                              r.base_velocity_m_s, r.base_omega_rad_s, com[:2] - mid[:2]])
        return np.clip(obs, self.observation_space.low, self.observation_space.high).astype(np.float32)

    def _info(self, terms: dict, recovered: bool = False) -> dict:
        return {"reward_terms": terms, "time_s": self.sim.time_s, "mode": self.executor.mode,
                "hot_side": self.hot_side, "max_temperature_C": float(self.reading.temperature_C.max()),
                "recovered": recovered, "fell": self.fallen, "hot_recovery_s": self.hot_recovery_s,
                **self.sim.plant_faults()}
