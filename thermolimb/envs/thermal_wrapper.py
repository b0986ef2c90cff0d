"""Joints that heat up, in any Gymnasium environment: :class:`ThermalWrapper`.

Each step the wrapper reads the torque each named joint was given and advances its winding temperature:

* **the torque**: a MuJoCo environment's actuator forces times their gears (``data.actuator_force``), this
  suite's PyBullet robots' applied joint torques (their rig's record: torque control applies exactly what was
  commanded), or ``torque=f(env) -> array`` for anything else; held over the step (an environment whose torque
  changes within a step should pass a function returning its mean);
* **the heat**: the user's saved models (the file ``fit`` or ``diagnose --save`` writes; one model for every
  joint when the file holds one actuator), run exactly (zero-order hold over the step) -- the first-order
  models of Jorgensen et al. (Joule heating, an effort bias, copper's coefficient) in one vectorised update,
  any other model through :meth:`~thermolimb.model.ThermalModel.simulate` carried from step to step; a model
  that does not read the ambient has its offset moved by how far ``ambient_C`` lies beyond the air it was
  identified in -- or this suite's plant with datasheet actuators (``plant=X8_9``: several masses, the lot).

What the policy sees: ``observe="append"`` adds the joints' temperatures (degC, in ``joints`` order) at the
end of a Box observation; ``"dict"`` makes the observation ``{"observation": ..., "temperature_C": ...}``;
``None`` leaves it alone.  ``info`` gets ``temperature_C``, ``time_to_limit_s`` (``inf``: never at this step's
torque) and ``derating`` (the share of torque :class:`~thermolimb.plant.protection.ThermalProtection` would
allow), arrays in ``joints`` order, and ``thermal_joints``.  Optional: ``penalty`` (reward per K above
``warning_C``, summed over joints), ``terminate`` (the episode ends when a joint reaches its limit),
``protect`` (each actuator's command scaled by its derating, as a drive derates: for torque-commanded
actuators).
"""

from __future__ import annotations

from pathlib import Path
from typing import Callable, Mapping, Sequence

import gymnasium as gym
import numpy as np

from ..model.arrays import ModelArrays, one_node
from ..model.experience import shifted
from ..model.parameter_units import NOT_GIVEN
from ..model.saved import ModelFile, SavedModel
from ..model.signals import Signals
from ..plant.plant import TEMPERATURE_RANGE_C
from ..plant.protection import ThermalProtection
from ..util.errors import UsageError
from .torque_readers import step_seconds, torque_reader

DEFAULT_MARGIN_K = 10.0  # warning_C defaults to this far below the limit
OBSERVE = ("append", "dict", None)


class ThermalWrapper(gym.Wrapper, gym.utils.RecordConstructorArgs):
    """Heat the named joints of ``env`` from the torques it applies (module docstring).

    Parameters
    ----------
    models
        A model file's path, a :class:`~thermolimb.model.saved.ModelFile`, or ``{joint: SavedModel}``; a file
        holding one actuator serves every joint.  Exactly one of ``models`` and ``plant``.
    plant
        An :class:`~thermolimb.plant.ActuatorSpec` (every joint) or one per joint: this suite's plant.
    joints
        The joints to heat: MuJoCo actuator names, the suite's robots' joint names; default every one.
    torque
        ``f(env) -> array`` of the joints' torques (N m), instead of reading them from the simulator.
    ambient_C, start_C
        The air's temperature and the windings' at reset (default: ambient), degC.
    limit_C, warning_C
        Each joint's limit (default: the model file's, else 90 degC) and where the penalty starts (default
        10 K below the limit).
    reset_heat
        Whether ``reset`` cools the joints to ``start_C`` (default); ``False`` carries the heat across
        episodes, as a robot set up again after a fall is still warm.
    torque_constant_Nm_per_A
        For models that heat from a current (their effort in A or mA): the motor's torque constant at the
        joint (N m per A), by which the joints' torques become currents.  Without it such a model is refused:
        an environment gives torques in N m.

    Raises
    ------
    UsageError
        A value out of its range (temperatures within -60 to 400 degC, a limit above the start, a penalty of
        zero or more), a model whose effort is not a torque in N m and cannot be made one, or ``step`` before
        ``reset``.
    """

    def __init__(
        self,
        env: gym.Env,
        models=None,
        plant=None,
        joints: Sequence[str] | None = None,
        torque: Callable[[gym.Env], np.ndarray] | None = None,
        ambient_C: float = 25.0,
        start_C: float | None = None,
        limit_C: float | None = None,
        warning_C: float | None = None,
        observe: str | None = "append",
        penalty: float = 0.0,
        terminate: bool = False,
        protect: bool = False,
        reset_heat: bool = True,
        torque_constant_Nm_per_A: float | None = None,
    ):
        gym.utils.RecordConstructorArgs.__init__(self, models=models, plant=plant, joints=joints,
                                                 torque=torque, ambient_C=ambient_C, start_C=start_C,
                                                 limit_C=limit_C, warning_C=warning_C, observe=observe,
                                                 penalty=penalty, terminate=terminate, protect=protect,
                                                 reset_heat=reset_heat,
                                                 torque_constant_Nm_per_A=torque_constant_Nm_per_A)
        gym.Wrapper.__init__(self, env)
        if (models is None) == (plant is None):
            raise UsageError("ThermalWrapper needs models (a model file) "
                             "or plant (datasheet actuators), one of them")
        if observe not in OBSERVE:
            raise UsageError(f"observe must be one of {OBSERVE}, got {observe!r}")
        low, high = TEMPERATURE_RANGE_C
        ambient_C = _checked("ambient_C", ambient_C, low, high)
        start_C = ambient_C if start_C is None else _checked("start_C", start_C, low, high)
        penalty = _checked("penalty", penalty, 0.0, np.inf, "(a reward taken per K above warning_C)")
        if joints is not None and (isinstance(joints, str) or not all(isinstance(j, str) for j in joints)
                                   or len(set(joints)) != len(joints) or not joints):
            raise UsageError("ThermalWrapper: joints must be a list "
                             f"of joint names, each once, got {joints!r}")
        self.reader = torque_reader(env, joints, torque)
        self.joints = self.reader.joints
        self.ambient_C, self.start_C = ambient_C, start_C
        self.observe, self.penalty, self.terminate, self.protect = observe, penalty, terminate, protect
        self.reset_heat = reset_heat
        self._started = False
        if plant is not None:
            self.heat = PlantHeat(plant, self.joints, self.ambient_C)
        else:
            saved = joint_models(models, self.joints)
            self.reader.per_effort = effort_scale(saved, torque_constant_Nm_per_A,
                                                  type(env.unwrapped).__name__)
            self.heat = ModelHeat(saved, self.ambient_C)
        limits = self.heat.limits_C if limit_C is None else np.full(len(self.joints),
                                                                   _checked("limit_C", limit_C, low, high))
        self.limit_C = np.where(np.isfinite(limits), limits, 90.0)
        below = np.flatnonzero(self.limit_C <= start_C)
        if below.size:  # every episode would end at its first step
            k = int(below[0])
            raise UsageError(f"{below.size} of {len(self.joints)} joints start at or above their limit "
                             f"({self.joints[k]}: limit {self.limit_C[k]:g} "
                             f"degC, start {start_C:.1f} degC); expected "
                             "limits above where the joints start "
                             "(limit_C and start_C; --limit-C, --ambient-C)")
        self.warning_C = self.limit_C - DEFAULT_MARGIN_K if warning_C is None else np.full(
            len(self.joints), _checked("warning_C", warning_C, low, high))
        if np.any(self.warning_C > self.limit_C):
            raise UsageError("ThermalWrapper: warning_C "
                             f"({np.max(self.warning_C):g} degC) must not lie above "
                             f"limit_C ({np.min(self.limit_C):g} degC)")
        self.protection = ThermalProtection(margin_K=DEFAULT_MARGIN_K + 5.0)
        self.dt_s = step_seconds(env)
        self.temperature_C = np.full(len(self.joints), self.start_C)
        low = np.full(len(self.joints), -273.15, np.float64)
        high = np.full(len(self.joints), np.inf, np.float64)
        temperatures = gym.spaces.Box(low, high, dtype=np.float64)
        space = env.observation_space
        if observe == "append":
            if not isinstance(space, gym.spaces.Box) or len(space.shape) != 1:
                raise UsageError("observe='append' needs a flat Box "
                                 f"observation; this environment's is {space}; "
                                 f"use observe='dict'")
            self.observation_space = gym.spaces.Box(np.concatenate([space.low.astype(np.float64), low]),
                                                    np.concatenate([space.high.astype(np.float64), high]),
                                                    dtype=np.float64)
        elif observe == "dict":
            self.observation_space = gym.spaces.Dict({"observation": space, "temperature_C": temperatures})

    def reset(self, *, seed=None, options=None):
        obs, info = self.env.reset(seed=seed, options=options)
        if self.reset_heat or not self._started:
            self.heat.reset(self.start_C)
            self.temperature_C = np.full(len(self.joints), self.start_C)
            self._started = True
        zeros = np.zeros(len(self.joints))
        return self._observation(obs), self._info(info, zeros, np.full(len(self.joints), np.inf))

    def step(self, action):
        if not self._started:  # as Gymnasium's OrderEnforcing refuses it: the temperatures are set by reset
            raise gym.error.ResetNeeded("ThermalWrapper: call reset() before "
                                        "step(): the windings' temperatures "
                                        "start at reset")
        if self.protect:
            action = self.reader.derated(self.env, action, self._derating())
        obs, reward, terminated, truncated, info = self.env.step(action)
        torque_Nm, velocity = self.reader.read(self.env)
        effort = torque_Nm if self.reader.per_effort is None else torque_Nm * self.reader.per_effort
        self.temperature_C, reach_s = self.heat.step(effort, velocity, self.dt_s, self.limit_C)
        over = np.maximum(self.temperature_C - self.warning_C, 0.0)
        if self.penalty:
            reward = float(reward) - self.penalty * float(over.sum())
        overheated = self.temperature_C >= self.limit_C
        if self.terminate and overheated.any():
            terminated = True
        info = self._info(info, torque_Nm, reach_s)
        info["overheated"] = [j for j, hot in zip(self.joints, overheated) if hot] if overheated.any() else []
        return self._observation(obs), reward, terminated, truncated, info

    def _derating(self) -> np.ndarray:
        """ThermalProtection's linear derating over its margin below each limit (inline: it runs every
        step)."""
        fraction = (self.limit_C - self.temperature_C) / self.protection.margin_K
        return np.minimum(np.maximum(fraction, self.protection.min_fraction), 1.0)

    def _observation(self, obs):
        if self.observe == "append":
            return np.concatenate([np.asarray(obs, np.float64), self.temperature_C])
        if self.observe == "dict":
            return {"observation": obs, "temperature_C": self.temperature_C.copy()}
        return obs

    def _info(self, info: dict, torque_Nm: np.ndarray, reach_s: np.ndarray) -> dict:
        info = dict(info)
        info.update(thermal_joints=list(self.joints), temperature_C=self.temperature_C.copy(),
                    torque_Nm=np.asarray(torque_Nm, float).copy(), time_to_limit_s=reach_s,
                    derating=self._derating())
        return info


def joint_models(models, joints: Sequence[str]) -> list[SavedModel]:
    """Each joint's saved model: by name, or one model (a ``SavedModel``, a file of one actuator) for every
    joint."""
    if isinstance(models, SavedModel):
        return [models] * len(joints)
    if isinstance(models, (str, Path)):
        models = ModelFile.load(models)
    if isinstance(models, ModelFile):
        models = dict(models.actuators)
    if not isinstance(models, Mapping) or not models:
        raise UsageError("models must be a model file, a ModelFile or {joint: SavedModel}")
    if len(models) == 1 and not set(joints) <= set(models):
        return [next(iter(models.values()))] * len(joints)
    missing = [j for j in joints if j not in models]
    if missing:
        raise UsageError(f"the models name {', '.join(models)}; no model for the joints {', '.join(missing)} "
                         f"(one model serves every joint: pass ModelFile.load(path)[actuator])")
    return [models[j] for j in joints]


class ModelHeat:
    """The joints' saved models, run exactly over each step."""

    def __init__(self, saved: Sequence[SavedModel], ambient_C: float):
        # in an air beyond the one a model's offset stands for, the offset follows it (Jorgensen et al. Eq.
        # 5), as predict and the monitor do
        self.models = [shifted(s.model, s.offset_shift_K(np.array([ambient_C]))) for s in saved]
        self.limits_C = np.array([np.nan if s.limit_C is None else s.limit_C for s in saved])
        # what each was fitted on (audit)
        self.experience = [dict(s.provenance).get("ranges") or {} for s in saved]
        self.ambient_C = ambient_C
        self.fast = all(one_node(m) for m in self.models)
        self.arrays = ModelArrays(self.models) if self.fast else None
        self.states: list[dict] = [{} for _ in self.models]
        self.T = np.zeros(len(self.models))

    def reset(self, start_C: float) -> None:
        self.T = np.full(len(self.models), start_C)
        self.states = [{} for _ in self.models]

    def step(
        self, torque: np.ndarray, velocity, dt: float, limit_C: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        if self.fast:  # one node: each actuator's exact step over dt at the torque held, all at once
            speed = np.abs(velocity) if velocity is not None and self.arrays.reads_speed else None
            steady, rate = self.arrays.forcing(torque, speed)
            self.T = steady + (self.T - steady) * np.exp(-rate * dt)
            return self.T.copy(), reach_s(self.T, steady, rate, limit_C)
        steady, rate = np.empty_like(self.T), np.empty_like(self.T)
        for k, model in enumerate(self.models):
            v = None if velocity is None else np.full(2, velocity[k])
            s = Signals(np.array([0.0, dt]), np.full(2, torque[k]), v, ambient_C=np.full(2, self.ambient_C))
            keep: dict = {}
            out = model.simulate(s, self.T[k], state=self.states[k] or None, keep=keep)
            self.states[k] = keep
            self.T[k] = out[-1]
            steady[k], rate[k] = keep["steady_C"], keep["rate_per_s"]
        return self.T.copy(), reach_s(self.T, steady, rate, limit_C)


TORQUE_UNITS = {"N m": 1.0, "Nm": 1.0, "N·m": 1.0, "mN m": 1e3}  # a torque in N m, per N m
CURRENT_UNITS = {"A": 1.0, "mA": 1e3}  # a current per A


def effort_scale(
    saved: Sequence[SavedModel], torque_constant_Nm_per_A: float | None, env_name: str
) -> float | None:
    """The factor turning the environment's torques (N m) into the effort the models heat from: ``None`` for
    models in N m, 1/k_t (times 1000 for mA) for models of a current given the torque constant; refused in one
    sentence otherwise (a current without a torque constant, a unit the suite cannot turn a torque into).  A
    model whose effort unit was never given is taken as N m (its log did not say; the file says so too)."""
    units = {dict(s.channel_units).get("effort", NOT_GIVEN) for s in saved}
    if len(units) > 1:
        raise UsageError("ThermalWrapper: the models heat from efforts in "
                         f"different units ({', '.join(sorted(units))}); "
                         f"expected one unit for every joint")
    unit = units.pop()
    if unit in TORQUE_UNITS or unit == NOT_GIVEN:
        factor = TORQUE_UNITS.get(unit, 1.0)
        return None if factor == 1.0 else factor
    if unit in CURRENT_UNITS:
        if torque_constant_Nm_per_A is None:
            raise UsageError(f"the model heats from a current in {unit}; "
                             f"{env_name} gives torques in N m: pass "
                             f"torque_constant_Nm_per_A (--torque-constant) or a model fitted on torque")
        k = _checked("torque_constant_Nm_per_A", torque_constant_Nm_per_A, 0.0, np.inf)
        if k == 0.0:
            raise UsageError("ThermalWrapper: torque_constant_Nm_per_A must be above 0 N m/A")
        return CURRENT_UNITS[unit] / k
    raise UsageError(f"the model heats from an effort in {unit}; "
                     f"{env_name} gives torques in N m, which the suite "
                     f"cannot turn into {unit}: use a model fitted on torque (N m) or on a current (A, mA)")


def _checked(name: str, value, low: float, high: float, what: str = "") -> float:
    """``value`` as a float within ``[low, high]``, or a UsageError naming it."""
    try:
        number = float(value)
    except (TypeError, ValueError):
        number = np.nan
    if not (np.isfinite(number) and low <= number <= high) or isinstance(value, bool):
        bounds = f"between {low:g} and {high:g} degC" if np.isfinite(high) else f">= {low:g}"
        raise UsageError(f"ThermalWrapper: {name} must be a finite "
                         f"number {bounds}{' ' + what if what else ''}, "
                         f"got {value!r}")
    return number


def reach_s(T: np.ndarray, steady: np.ndarray, rate, limit_C: np.ndarray) -> np.ndarray:
    """When each first-order response reaches its limit at the current inputs (s; 0 at or past it, inf
    never)."""
    out = np.where(T >= limit_C, 0.0, np.inf)
    rising = (steady > limit_C) & (T < limit_C)
    if rising.any():  # ln((T - u) / (L - u)) / rate, only where the steady state lies beyond the limit
        ratio = (T[rising] - steady[rising]) / (limit_C[rising] - steady[rising])
        out[rising] = np.log(ratio) / (rate[rising] if np.ndim(rate) else rate)
    return out


class PlantHeat:
    """This suite's plant with datasheet actuators."""

    def __init__(self, plant, joints: Sequence[str], ambient_C: float):
        from ..plant import ActuatorSpec

        specs = [plant] * len(joints) if isinstance(plant, ActuatorSpec) else list(plant)
        if len(specs) != len(joints) or not all(isinstance(s, ActuatorSpec) for s in specs):
            raise UsageError(f"plant must be an ActuatorSpec or one per joint ({len(joints)}), got {plant!r}")
        self.joints, self.specs, self.ambient_C = list(joints), specs, ambient_C
        self.limits_C = np.array([s.winding_limit_C for s in specs], float)
        # the plant holds a torque at its peak
        self.peak_Nm = np.array([s.effort_limit for s in specs], float)
        self.plant = self.make(ambient_C)

    def make(self, start_C: float):
        from ..plant import PlantEffects, ThermalPlant

        return ThermalPlant(self.joints, self.specs, PlantEffects(), ambient_C=self.ambient_C,
                            initial_C=start_C)

    def reset(self, start_C: float) -> None:
        self.plant = self.make(start_C)

    def step(
        self, torque: np.ndarray, velocity, dt: float, limit_C: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        before = self.plant.winding_C.copy()
        self.plant.step(torque, velocity, dt)
        T = self.plant.winding_C.copy()
        rate = (T - before) / dt  # at the current rate (the plant's several masses have no one closed form)
        with np.errstate(divide="ignore", invalid="ignore"):
            t = np.where(rate > 0, (limit_C - T) / rate, np.inf)
        return T, np.where(T >= limit_C, 0.0, t)
